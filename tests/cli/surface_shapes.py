"""Closed test surfaces written by our own code (the paper's sphere and
pyramids), shared by the command-line tests and the benchmarks."""
import math


def write_off(path, pts, tris):
    with open(path, "w") as f:
        f.write("OFF\n%d %d 0\n" % (len(pts), len(tris)))
        f.writelines("%r %r %r\n" % tuple(p) for p in pts)
        f.writelines("3 %d %d %d\n" % tuple(t) for t in tris)


def pyramid(cx, cy, cz, height):
    """A square pyramid on a unit base centred at (cx, cy, cz); a negative
    height points it down (its facets turned so they still face out)."""
    pts = [(cx - .5, cy - .5, cz), (cx + .5, cy - .5, cz), (cx + .5, cy + .5, cz), (cx - .5, cy + .5, cz),
           (cx, cy, cz + height)]
    tris = [(0, 2, 1), (0, 3, 2), (0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)]
    if height < 0:
        tris = [(a, c, b) for a, b, c in tris]
    return pts, tris


def paper_pyramids():
    """The paper's two almost touching pyramids (§9.8): the second one's tip
    offset (0.1454, 0.3569, 0.0019) from the centre of the first one's base."""
    p1, t1 = pyramid(0, 0, 0, -1)
    p2, t2 = pyramid(0.1454, 0.3569, 1.0019, -1)
    return p1 + p2, t1 + [(a + 5, b + 5, c + 5) for a, b, c in t2]


def icosphere(levels):
    t = (1 + math.sqrt(5)) / 2
    pts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
           (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    pts = [tuple(c / math.sqrt(sum(x * x for x in p)) for c in p) for p in pts]
    tris = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
            (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11),
            (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(levels):
        mid = {}

        def m(a, b):
            k = (min(a, b), max(a, b))
            if k not in mid:
                p = [(x + y) / 2 for x, y in zip(pts[a], pts[b])]
                n = math.sqrt(sum(x * x for x in p))
                pts.append(tuple(x / n for x in p))
                mid[k] = len(pts) - 1
            return mid[k]
        nxt = []
        for a, b, c in tris:
            ab, bc, ca = m(a, b), m(b, c), m(c, a)
            nxt += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        tris = nxt
    return pts, tris
