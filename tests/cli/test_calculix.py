"""A real solver on vdmesh meshes: Abaqus decks written by `vdmesh mesh` run in
CalculiX (ccx) and give the displacements of beam theory.

- Uniaxial tension of a bar, the loaded end free to contract: tip displacement
  F·L/(E·A), C3D4 within 0.5 %, C3D10 within 0.1 % (the issue's bounds; a
  uniform stress state is reproduced by either element, so both are far inside).
- Two materials in series (two regions sharing an interface face), Poisson's
  ratio 0 so that the interface does not constrain lateral contraction:
  F·(L1/E1 + L2/E2)/A within the same bounds.
- A cantilever under a tip load, where element order matters: C3D10 within 2 %
  of Timoshenko's P·L³/(3EI) + P·L/(κGA); C3D4 is stiffer than C3D10 (shear
  locking of linear tetrahedra), which shows that the 10-node deck really is
  second order.
"""
import os
import shutil
import subprocess

from cli_support import check, finish, read_abaqus_deck, run, tmpdir

L, B, H = 10.0, 1.0, 1.0


def write_bar_obj(path, cuts):
    """Box [0,L]x[0,B]x[0,H] as an OBJ whose groups become face ids: `fixed`
    (x = 0), `tip` (x = L), `side`, and one `interface` per inner cut x = c,
    which makes the pieces separate regions."""
    xs = [0.0] + list(cuts) + [L]
    verts, faces = [], []

    def v(x, y, z):
        verts.append((x, y, z))
        return len(verts)

    ring = []  # per x station, the 4 corners (y, z) = (0,0), (B,0), (B,H), (0,H)
    for x in xs:
        ring.append([v(x, 0, 0), v(x, B, 0), v(x, B, H), v(x, 0, H)])
    out = lambda q: faces.append(q)
    groups = {"fixed": [], "tip": [], "side": [], "interface": []}
    a = ring[0]
    groups["fixed"].append((a[0], a[3], a[2], a[1]))  # normal -x (outward)
    b = ring[-1]
    groups["tip"].append((b[0], b[1], b[2], b[3]))  # normal +x
    for i in range(len(xs) - 1):
        p, q = ring[i], ring[i + 1]
        for k in range(4):
            k2 = (k + 1) % 4
            groups["side"].append((p[k], p[k2], q[k2], q[k]))
    for c in ring[1:-1]:
        groups["interface"].append((c[0], c[1], c[2], c[3]))
    with open(path, "w") as f:
        for x, y, z in verts:
            f.write("v %r %r %r\n" % (x, y, z))
        for name, quads in groups.items():
            if not quads:
                continue
            f.write("g %s\n" % name)
            for q in quads:
                f.write("f %d %d %d\nf %d %d %d\n" % (q[0], q[1], q[2], q[0], q[2], q[3]))


def nearest_node(nodes, p):
    return min(nodes, key=lambda n: sum((a - b) ** 2 for a, b in zip(nodes[n], p)))


def run_ccx(tmp, name, mesh_inp, materials, step):
    """Runs a deck made of the mesh, `materials` ({ELSET: (E, nu)}) and `step`;
    returns {node: (ux, uy, uz)} of the printed nodes, or None."""
    deck = os.path.join(tmp, name + ".inp")
    with open(deck, "w") as f:
        f.write("*HEADING\nvdmesh CalculiX check %s\n*INCLUDE, INPUT=%s\n" % (name, os.path.basename(mesh_inp)))
        for i, (elset, (e, nu)) in enumerate(sorted(materials.items())):
            f.write("*MATERIAL, NAME=M%d\n*ELASTIC\n%r, %r\n*SOLID SECTION, ELSET=%s, MATERIAL=M%d\n"
                    % (i, e, nu, elset, i))
        f.write(step)
    p = subprocess.run(["ccx", name], cwd=tmp, capture_output=True, text=True, timeout=900)
    dat = os.path.join(tmp, name + ".dat")
    ok = p.returncode == 0 and "*ERROR" not in p.stdout and os.path.exists(dat)
    check(ok, "ccx runs %s (exit %d)" % (name, p.returncode))
    if not ok:
        print(p.stdout[-2000:])
        return None
    u = {}
    for line in open(dat):
        parts = line.split()
        if len(parts) == 4 and parts[0].isdigit():
            u[int(parts[0])] = tuple(float(x) for x in parts[1:])
    return u


def mesh_bar(tmp, name, cuts, order, size):
    obj = os.path.join(tmp, name + ".obj")
    write_bar_obj(obj, cuts)
    inp = os.path.join(tmp, name + "_mesh.inp")
    code, out, err = run("mesh", obj, "-o", inp, "--size", size, "--order", order, "--quiet")
    check(code == 0, "vdmesh mesh %s --order %d (exit %d) %s" % (name, order, code, err.strip()[-300:]))
    if code != 0:
        return None
    nodes, elsets, _, _ = read_abaqus_deck(inp)
    want = 10 if order == 2 else 4
    counts = {len(e) - 1 for es in elsets.values() for e in es}
    check(counts == {want}, "%s: every element has %d nodes (%s)" % (name, want, sorted(counts)))
    # The bar's shape is kept exactly: its tetrahedra fill L x B x H.
    volume = 0.0
    for es in elsets.values():
        for e in es:
            p = [nodes[n] for n in e[1:5]]
            a, b, c = ([p[k][i] - p[0][i] for i in range(3)] for k in (1, 2, 3))
            volume += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                       + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6
    check(abs(volume - L * B * H) < 1e-9 * L * B * H, "%s: tetrahedra fill the bar (volume %.12g)" % (name, volume))
    return inp, nodes, elsets


def axial_step(nodes, force):
    """x = 0 held axially; two corner nodes remove the rigid motions without
    stopping lateral contraction; traction on `tip` totalling `force`."""
    a = nearest_node(nodes, (0, 0, 0))
    b = nearest_node(nodes, (0, B, 0))
    return ("*BOUNDARY\nfixed_Nodes, 1, 1, 0.\n%d, 2, 3, 0.\n%d, 3, 3, 0.\n*STEP\n*STATIC\n"
            "*DSLOAD\ntip, P, %r\n*NODE PRINT, NSET=tip_Nodes\nU\n*END STEP\n" % (a, b, -force / (B * H)))


def region_sets_by_x(nodes, elsets):
    """ELSET names of the regions, from the lowest mean x to the highest."""
    def mean_x(es):
        return sum(nodes[n][0] for e in es for n in e[1:5]) / (4 * len(es))
    return sorted(elsets, key=lambda s: mean_x(elsets[s]))


def tip_mean(u, component):
    return sum(v[component] for v in u.values()) / len(u)


def main():
    if not shutil.which("ccx"):
        print("not run: ccx (calculix-ccx) is not installed")
        finish()
        return
    tmp = tmpdir()
    E, NU, F = 210000.0, 0.3, 1000.0

    # Uniaxial bar, one material.
    for order, bound in ((1, 0.005), (2, 0.001)):
        made = mesh_bar(tmp, "bar%d" % order, [], order, 0.5)
        if not made:
            continue
        inp, nodes, elsets = made
        u = run_ccx(tmp, "tension%d" % order, inp, {s: (E, NU) for s in elsets}, axial_step(nodes, F))
        if u:
            exact = F * L / (E * B * H)
            got = tip_mean(u, 0)
            spread = max(v[0] for v in u.values()) - min(v[0] for v in u.values())
            check(abs(got - exact) <= bound * exact,
                  "bar C3D%d: tip ux %.6e vs F.L/(E.A) %.6e (error %.2e, bound %g); spread over the tip %.1e"
                  % (10 if order == 2 else 4, got, exact, abs(got - exact) / exact, bound, spread))

    # Two materials in series.
    E1, E2, L1 = 210000.0, 70000.0, 4.0
    for order, bound in ((1, 0.005), (2, 0.001)):
        made = mesh_bar(tmp, "series%d" % order, [L1], order, 0.5)
        if not made:
            continue
        inp, nodes, elsets = made
        check(len(elsets) == 2, "series bar: two regions (%s)" % sorted(elsets))
        if len(elsets) != 2:
            continue
        left, right = region_sets_by_x(nodes, elsets)
        # Each region's node set holds its nodes: x <= L1 on the left, x >= L1
        # on the right (ccx reads them in the run below).
        _, _, nsets, _ = read_abaqus_deck(inp)
        for name, side in ((left, lambda x: x <= L1 + 1e-9), (right, lambda x: x >= L1 - 1e-9)):
            want = {n for n, p in nodes.items() if side(p[0])}
            got = nsets.get(name + "_Nodes", set())
            check(got == want, "series bar C3D%d: %s_Nodes holds the region's %d nodes (%d, %d missing, %d extra)"
                  % (10 if order == 2 else 4, name, len(want), len(got), len(want - got), len(got - want)))
        u = run_ccx(tmp, "series_run%d" % order, inp, {left: (E1, 0.0), right: (E2, 0.0)}, axial_step(nodes, F))
        if u:
            exact = F * (L1 / E1 + (L - L1) / E2) / (B * H)
            got = tip_mean(u, 0)
            check(abs(got - exact) <= bound * exact,
                  "two-material bar C3D%d: tip ux %.6e vs F(L1/E1 + L2/E2)/A %.6e (error %.2e, bound %g)"
                  % (10 if order == 2 else 4, got, exact, abs(got - exact) / exact, bound))

    # Cantilever: clamped at x = 0, tip load P in -z spread over the tip nodes.
    P = 10.0
    inertia, area, G, kappa = B * H ** 3 / 12, B * H, E / (2 * (1 + NU)), 5.0 / 6.0
    timoshenko = P * L ** 3 / (3 * E * inertia) + P * L / (kappa * G * area)
    deflection = {}
    for order in (1, 2):
        made = mesh_bar(tmp, "cantilever%d" % order, [], order, 0.5)
        if not made:
            continue
        inp, nodes, elsets = made
        tip = [n for n, p in nodes.items() if abs(p[0] - L) < 1e-9]
        step = ("*BOUNDARY\nfixed_Nodes, 1, 3, 0.\n*STEP\n*STATIC\n*CLOAD\n" +
                "".join("%d, 3, %r\n" % (n, -P / len(tip)) for n in tip) +
                "*NODE PRINT, NSET=tip_Nodes\nU\n*END STEP\n")
        u = run_ccx(tmp, "bend%d" % order, inp, {s: (E, NU) for s in elsets}, step)
        if u:
            deflection[order] = -tip_mean(u, 2)
    if 2 in deflection:
        err = abs(deflection[2] - timoshenko) / timoshenko
        check(err <= 0.02, "cantilever C3D10: tip deflection %.5e vs Timoshenko %.5e (error %.2f %%, bound 2 %%)"
              % (deflection[2], timoshenko, 100 * err))
    if 1 in deflection and 2 in deflection:
        check(deflection[1] < deflection[2],
              "cantilever: C3D4 is stiffer than C3D10 (%.5e < %.5e, %.1f %% below Timoshenko)"
              % (deflection[1], deflection[2], 100 * (timoshenko - deflection[1]) / timoshenko))
    finish()


if __name__ == "__main__":
    main()
