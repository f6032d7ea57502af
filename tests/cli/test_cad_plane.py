"""gmsh_simple_plane.brep (27 solids, 108 faces) from the command line, apart
from test_cad.py: its runs are the longest of the CAD tests (over 20 minutes
together under the sanitizers), and on their own they run beside the rest.
Its default size, a cap fold round undone, 0.6 times its size, and the
uniform chord heights' retries."""
import json
import os

from cad_support import mesh_as, out, tets_in_solids
from cli_support import check, data, finish, run

# gmsh_simple_plane.brep at its default size: recovered on the uniform chord
# heights (test_cad_corpus), with interior vertices and cap fold splits.
path = data("cad-assembly/gmsh_simple_plane.brep")
if path:
    target = os.path.join(out, "simple_plane.vtu")
    report = os.path.join(out, "simple_plane.json")
    code, table, err = run("mesh", path, "-o", target, "--report", report)
    rep = json.load(open(report)) if code == 0 else None
    # The report table says how many solids are off by over 0.5 % (6 of 27
    # here on 2026-11-28, 4 on 2026-12-01), apart from the per-solid rows.
    off = [line for line in table.splitlines() if "volumes off by over 0.5 %" in line]
    bad = [v for v in rep["cad"]["volumes"] if abs(v["mesh"] / v["cad"] - 1) > 0.005] if rep else []
    check(len(off) == 1 and (" %d of 27 solids (largest " % len(bad)) in off[0] and len(bad) > 0,
          "simple plane: the table counts the solids off by over 0.5 %% (%s, %d in the JSON)" % (off, len(bad)))
    check(code == 0 and rep["interior"]["cap_folds_split"] > 0 and rep["cad"]["solids"] == 27 and rep["complete"],
          "simple plane: meshed (exit %d, %s)" % (code, rep["interior"] if rep else err.strip()[-300:]))
    if code == 0:
        vol, region = tets_in_solids(target, 27, "simple plane")
        # The wing shells (Solid9 to 12, 3 mm thick): recovery splits their
        # outer faces only, and split vertices on the CAD surface took them
        # 0.54 to 0.73 % over their volume; where a split vertex would take a
        # solid farther past the tolerance it now stays on the chord
        # (surface/volume_keeper.h). 0.384 to 0.400 % on 2026-11-28.
        cad = {int(v["name"][len("Solid"):]): v["cad"] for v in rep["cad"]["volumes"]}
        wings = {k: vol[region == k].sum() / cad[k] - 1 for k in (9, 10, 11, 12)}
        check(all(abs(e) < 0.005 for e in wings.values()) and rep["delaunayzation"]["splits_on_chord_for_volume"] > 0,
              "simple plane: the wing shells within 0.5 %% of their CAD volume (%s; %d splits kept on the chord "
              "for a volume; meshio)" % (", ".join("Solid%d %+.3f %%" % (k, 100 * e) for k, e in sorted(wings.items())),
                                         rep["delaunayzation"]["splits_on_chord_for_volume"]))
        # The nose pieces (Solid1 to 4): its tip is a quarter cone 0.28 mm
        # across (Face74, Face80), crossed by single 90 deg chords at every
        # chord height until its arcs were held to 60 deg (cad_remesh.cpp):
        # Solid1 and 3 were 0.70 % short, Face74 4.8 % (-0.39 % and -1.4 %
        # on 2026-12-01).
        nose = {k: vol[region == k].sum() / cad[k] - 1 for k in (1, 2, 3, 4)}
        tips = {a["name"]: a["mesh"] / a["cad"] - 1 for a in rep["cad"]["areas"] if a["name"] in ("Face74", "Face80")}
        check(all(abs(e) < 0.005 for e in nose.values()) and len(tips) == 2 and all(abs(e) < 0.02 for e in tips.values()),
              "simple plane: the nose pieces within 0.5 %% of their CAD volume (%s) and its tip cones' areas within 2 %% "
              "(%s; meshio, report)" % (", ".join("Solid%d %+.3f %%" % (k, 100 * e) for k, e in sorted(nose.items())),
                                        ", ".join("%s %+.2f %%" % (n, 100 * e) for n, e in sorted(tips.items()))))

# A cap fold round undone (pipeline/mesher.cpp): gmsh_simple_plane.brep at
# size 0.2 recovers its surface, its interior vertices and the first round
# of cap fold splits, but the recovery after the second round runs away at
# the wing roots. That round is undone and the mesh before it kept. Until
# 2026-11-27 the whole run was made again cautiously (below). Which runs get
# there is chaotic: until 2026-11-28 the default size (0.19446) did, then
# no more once split vertices stayed on the chord for a solid's volume; at
# 0.2 and 0.22 it does, at 0.24 and 0.26 the cautious run comes instead
# (2026-11-28); until 2026-11-26 this test ran at chord heights 0.001, then
# 0.0015, each of which met it until a change of the face remesher.
path = data("cad-assembly/gmsh_simple_plane.brep")
if path:
    code, rep, target, err = mesh_as("simple_plane_02", path, "--size", "0.2", "--quiet")
    check(code == 0 and rep["interior"]["cap_fold_round_undone"] and not rep["interior"]["cautious_retry"]
          and rep["interior"]["cap_folds_split"] > 0 and rep["cad"]["solids"] == 27 and rep["complete"],
          "simple plane at size 0.2: meshed with its last cap fold round undone (exit %d, %s)"
          % (code, rep["interior"] if rep else err.strip()[-300:]))
    if code == 0:
        tets_in_solids(target, 27, "simple plane at size 0.2")

# gmsh_simple_plane.brep at size 0.1167 (0.6 times its default 0.19446;
# which tessellation of the chain meshes moves with the size, and at
# 0.116678 this fault did not show): on the uniform chords' third volume
# round, OpenCASCADE gave the fuselage's inside faces (Face102, Face103) 270
# facets instead of 972, so their remeshing asked for 120 times their facets,
# over the per-face limit of 50, and they kept OpenCASCADE's: the two shells
# behind them (Solid5, Solid6, held at the uniform chords, so no round looks
# at them) came out 3.67 % over their volume. Faces past the limit are now
# remeshed while the whole surface stays within its budget (cad_remesh.cpp,
# plan_remeshing), and a round that pushes a held solid over the tolerance
# is refused (cad_model.h); either alone keeps the shells in. Measured
# 2026-11-28: Solid5 and Solid6 -0.28 %, the worst solid (a nose piece)
# -1.06 % (-1.27 % with the refusal alone), 719k tetrahedra.
path = data("cad-assembly/gmsh_simple_plane.brep")
if path:
    code, rep, target, err = mesh_as("simple_plane_fine", path, "--size", "0.1167", "--quiet")
    check(code == 0, "simple plane at 0.6 times its size meshes (exit %d: %s)" % (code, err.strip()[-300:]))
    if code == 0:
        vol, region = tets_in_solids(target, 27, "simple plane at 0.6 times its size")
        cad = {int(v["name"][len("Solid"):]): v["cad"] for v in rep["cad"]["volumes"]}
        error = {k: abs(vol[region == k].sum() / c - 1) for k, c in cad.items()}
        shown = ", ".join("Solid%d %.3f %%" % (k, 100 * e) for k, e in sorted(error.items()) if e > 0.004)
        check(vol.min() > 0 and len(error) == 27 and error[5] < 0.005 and error[6] < 0.005,
              "simple plane at 0.6 times its size: the shells behind the fuselage's inside within 0.5 %% "
              "(Solid5 %.3f %%, Solid6 %.3f %%; meshio)" % (100 * error[5], 100 * error[6]))
        check(max(error.values()) < 0.015,
              "simple plane at 0.6 times its size: every solid within 1.5 %% of its CAD volume (over 0.4 %%: %s)" % shown)


def meshes_on_uniform_chords(size, height, which, stops, stalls):
    """gmsh_simple_plane.brep at `size` meshes on the uniform chord heights
    at `height` (as the progress line writes it, `which` of the first), after
    `stops` recoveries stopped and `stalls` stalled (tried again with shell
    splits), each said on a progress line."""
    path = data("cad-assembly/gmsh_simple_plane.brep")
    if not path:
        return
    code, rep, target, err = mesh_as("simple_plane_" + size.replace(".", ""), path, "--size", size, timeout=1800)
    on_it = "tessellate CAD faces again at 20 deg, chord height %s everywhere" % height in err
    stopped = [line for line in err.splitlines() if line.startswith("vdmesh: recovery stopped: ")]
    stalled = [line for line in err.splitlines() if line.startswith("vdmesh: recovery stalled: ")]
    check(code == 0 and rep["complete"] and rep["cad"]["solids"] == 27 and on_it and len(stopped) == stops
          and rep["cad"]["recovery_retries"] == stops and len(stalled) == stalls
          and rep["delaunayzation"]["shell_splits"] == (stalls > 0)
          and ("recovery stalled (mid-point splits)" in rep["seconds"]) == (stalls > 0),
          "simple plane at size %s: meshed on the uniform chords at %s of their height, after %d recoveries "
          "stopped and %d stalled, each said on the progress lines (exit %d, %s)"
          % (size, which, stops, stalls, code, [line[:90] for line in stopped + stalled] if code == 0 else err.strip()[-300:]))
    if code == 0:
        tets_in_solids(target, 27, "simple plane at size " + size)


# gmsh_simple_plane.brep at size 0.32: the first tessellation's recovery ran
# away at the thin wings, and the one on the uniform chord heights (size /
# 500, 0.00064) stopped with 46 facets of a wing root left after 48 passes;
# then the other angles ran away too, and the run ended in exit 4 (at 0.35
# after 198 s). The uniform chords are now tried again at half their height
# (TessellationChain, kUniformChordRetries), which meshes it: 575,174
# tetrahedra in 33 s on 2026-11-28 (0.38, 0.4 and 0.45 mesh too, at a
# quarter of the height for the first two). Since the nose's pointed cones
# keep their arcs under 60 deg (cad_remesh.cpp, 2026-12-01) the half, the
# quarter and three quarters of the height stop too (48 to 131 facets
# left), and three eighths meshes it: 648,558 tetrahedra, but its five
# stopped recoveries took over 10 minutes under the sanitizers. No longer
# run here: 0.3786 (below) shows the retries.

# gmsh_simple_plane.brep at size 0.3786: the uniform chords stopped at their
# height, at half and at a quarter of it (stalls and runaways where the wing's
# skins meet at small angles), and the run ended in exit 4, as at 5 of 10
# sizes sampled between 0.30 and 0.43 (2026-11-28). Three quarters and three
# eighths of the height come next now (kUniformChordRetries): here three
# quarters meshes it, 437,912 tetrahedra in 62 s (its smallest angle 0.0034
# deg, one tetrahedron; the next 0.52 deg).
meshes_on_uniform_chords("0.3786", "0.0005679", "three quarters", 4, 0)

# gmsh_simple_plane.brep at size 0.4067: every link of the chain stopped
# (the uniform heights stalled with 46 to 118 facets of 3e-7 to 5e-7 around
# the CAD vertex where the wing root's skins meet the fuselage; exit 4 after
# 46 s until 2026-11-29). The chain then runs once more with the edges from
# corners split on concentric shells (cad_mesher.cpp, mesh_chain_or_shells),
# and its first uniform height meshes: 232,400 tetrahedra, 0.70 deg. Since
# the nose's pointed cones keep their arcs under 60 deg (2026-12-01) 0.4067
# meshes on a quarter of the uniform height; of 12 sizes sampled between
# 0.39 and 0.47, 0.435, 0.445 and 0.46 stop on every link and mesh so.
# 0.435: 10 recoveries stopped (57 s), then 263,078 tetrahedra, 2.08 deg.
path = data("cad-assembly/gmsh_simple_plane.brep")
if path:
    code, rep, target, err = mesh_as("simple_plane_0435", path, "--size", "0.435", timeout=1800)
    again = "every tessellation's recovery stopped; all again with shell splits from corners" in err
    check(code == 0 and again and rep["delaunayzation"]["shell_splits"]
          and "recoveries stopped (mid-point splits)" in rep["seconds"] and rep["cad"]["recovery_retries"] == 1,
          "simple plane at size 0.435: every link stopped, then meshed with shell splits on the uniform chords "
          "(exit %d, %s)" % (code, err.strip()[-300:] if code else "retries %d" % rep["cad"]["recovery_retries"]))
    if code == 0:
        tets_in_solids(target, 27, "simple plane at size 0.435")

finish()
