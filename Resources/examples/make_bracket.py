#!/usr/bin/env python3
"""Writes the bundled demo surface, bracket.obj: an L-shaped bracket with a
rectangular hole through its base plate, built from unit voxels so that its
volume is exact (voxel count x voxel volume). Each planar side of the solid
is one OBJ group, so the mesher gets topological face ids.

Run: python3 Resources/examples/make_bracket.py Resources/examples/bracket.obj
"""
import sys

NX, NY, NZ = 12, 4, 8   # voxels along x (length), y (depth), z (height)
SIZE = 2.5              # voxel edge, mm


def solid(i, j, k):
    """The L profile: a base plate 2 voxels thick, an upright 2 voxels wide,
    and a 4 x 2 hole through the plate."""
    if not (0 <= i < NX and 0 <= j < NY and 0 <= k < NZ):
        return False
    in_base = k < 2
    in_upright = i < 2
    in_hole = 6 <= i < 10 and 1 <= j < 3 and k < 2
    return (in_base or in_upright) and not in_hole


def main(path):
    vertices, index = [], {}
    groups = {}

    def vid(p):
        if p not in index:
            index[p] = len(vertices) + 1
            vertices.append(p)
        return index[p]

    # A boundary square of voxel (i, j, k) on side (axis, sign), split into two
    # triangles oriented out of the solid.
    for i in range(NX):
        for j in range(NY):
            for k in range(NZ):
                if not solid(i, j, k):
                    continue
                for axis in range(3):
                    for sign in (-1, 1):
                        n = [i, j, k]
                        n[axis] += sign
                        if solid(*n):
                            continue
                        plane = [i, j, k][axis] + (1 if sign > 0 else 0)
                        u, v = [a for a in range(3) if a != axis]
                        corners = []
                        for du, dv in ((0, 0), (1, 0), (1, 1), (0, 1)):
                            c = [i, j, k]
                            c[axis] = plane
                            c[u] += du
                            c[v] += dv
                            corners.append(vid(tuple(c)))
                        # (u, v, axis) is right-handed when (axis+1)%3 == u.
                        right_handed = (axis + 1) % 3 == u
                        if right_handed != (sign > 0):
                            corners.reverse()
                        key = (axis, sign, plane)
                        groups.setdefault(key, []).append((corners[0], corners[1], corners[2]))
                        groups[key].append((corners[0], corners[2], corners[3]))

    with open(path, "w") as f:
        f.write("# vdmesh demo: L-bracket with a hole, %d voxels of %g mm\n" % (
            sum(solid(i, j, k) for i in range(NX) for j in range(NY) for k in range(NZ)), SIZE))
        for p in vertices:
            f.write("v %g %g %g\n" % tuple(SIZE * c for c in p))
        for n, key in enumerate(sorted(groups), start=1):
            f.write("g face_%d\n" % n)
            for t in groups[key]:
                f.write("f %d %d %d\n" % t)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "bracket.obj")
