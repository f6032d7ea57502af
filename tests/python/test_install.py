"""`cmake --install` into a temporary DESTDIR: the program, the Python module,
the C++ library (find_package(vdmesh)) and the FreeCAD workbench land where the
README says, and work from there.

ctest python.install passes the build's settings through the environment:
VDMESH_BUILD_DIR, VDMESH_INSTALL_PREFIX, VDMESH_PYTHON_INSTALL_DIR,
VDMESH_FREECAD_MOD_DIR, VDMESH_SOURCE_DIR, CMAKE_COMMAND."""
import filecmp
import os
import re
import subprocess
import sys
import tempfile
import unittest

ENV = os.environ


def under(destdir, path):
    """Where an absolute install path lands below DESTDIR."""
    return os.path.join(destdir, path.lstrip("/"))


class Install(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.destdir = tempfile.mkdtemp(prefix="vdmesh-install-")
        env = dict(ENV, DESTDIR=cls.destdir)
        subprocess.run([ENV["CMAKE_COMMAND"], "--install", ENV["VDMESH_BUILD_DIR"]], env=env, check=True,
                       capture_output=True, timeout=600)
        prefix = ENV["VDMESH_INSTALL_PREFIX"]
        pydir = ENV["VDMESH_PYTHON_INSTALL_DIR"]
        cls.bin = under(cls.destdir, os.path.join(prefix, "bin", "vdmesh"))
        cls.pydir = under(cls.destdir, pydir if os.path.isabs(pydir) else os.path.join(prefix, pydir))
        cls.mod = under(cls.destdir, ENV["VDMESH_FREECAD_MOD_DIR"])

    def test_program_runs(self):
        self.assertTrue(os.access(self.bin, os.X_OK), self.bin)
        p = subprocess.run([self.bin, "mesh", "--help"], capture_output=True, text=True, timeout=60)
        self.assertEqual(p.returncode, 0)
        self.assertIn("usage: vdmesh mesh", p.stdout)

    def test_program_meshes_cad_with_the_installed_plugin(self):
        # The plugin lands in <prefix>/lib/vdmesh, where the program looks for it.
        import gmsh
        work = tempfile.mkdtemp(prefix="vdmesh-install-cad-")
        brep = os.path.join(work, "box.brep")
        gmsh.initialize()
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.occ.addBox(0, 0, 0, 2, 1, 1)
        gmsh.model.occ.synchronize()
        gmsh.write(brep)
        gmsh.finalize()
        plugin = os.path.join(os.path.dirname(os.path.dirname(self.bin)), "lib", "vdmesh", "libvdmesh_cad.so")
        self.assertTrue(os.path.isfile(plugin), plugin)
        out = os.path.join(work, "box.vtu")
        p = subprocess.run([self.bin, "mesh", brep, "-o", out, "--size", "0.5", "--quiet"], capture_output=True,
                           text=True, timeout=120)
        self.assertEqual(p.returncode, 0, p.stderr)
        p = subprocess.run([self.bin, "info", out], capture_output=True, text=True, timeout=60)
        volume = re.search(r"region 1: volume ([0-9.e+-]+)", p.stdout)
        self.assertTrue(volume, p.stdout)
        self.assertAlmostEqual(float(volume.group(1)), 2.0, places=9)

    def test_cpp_library_builds_and_runs_the_example(self):
        # Resources/examples/cpp, configured against the installed package only
        # (CMAKE_PREFIX_PATH = the DESTDIR's prefix; the build tree is not seen).
        import gmsh
        work = tempfile.mkdtemp(prefix="vdmesh-install-cpp-")
        example = os.path.join(ENV["VDMESH_SOURCE_DIR"], "Resources", "examples", "cpp")
        prefix = under(self.destdir, ENV["VDMESH_INSTALL_PREFIX"])
        build = os.path.join(work, "build")
        p = subprocess.run([ENV["CMAKE_COMMAND"], "-S", example, "-B", build, "-DCMAKE_BUILD_TYPE=Release",
                            "-DCMAKE_PREFIX_PATH=" + prefix], capture_output=True, text=True, timeout=600)
        self.assertEqual(p.returncode, 0, p.stdout + p.stderr)
        p = subprocess.run([ENV["CMAKE_COMMAND"], "--build", build], capture_output=True, text=True, timeout=1200)
        self.assertEqual(p.returncode, 0, p.stdout[-4000:] + p.stderr[-4000:])
        with open(os.path.join(build, "CMakeCache.txt")) as f:
            cache = f.read()
        self.assertIn("vdmesh_DIR:PATH=" + os.path.join(prefix, "lib", "cmake", "vdmesh"), cache)
        brep = os.path.join(work, "cylinder.brep")
        gmsh.initialize()
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.occ.addCylinder(0, 0, 0, 0, 0, 3, 1)
        gmsh.model.occ.synchronize()
        gmsh.write(brep)
        gmsh.finalize()
        box_out, part_out = os.path.join(work, "box.vtu"), os.path.join(work, "cylinder.inp")
        p = subprocess.run([os.path.join(build, "mesh_box_and_part"), box_out, brep, part_out], capture_output=True,
                           text=True, timeout=600)
        self.assertEqual(p.returncode, 0, p.stdout + p.stderr)
        self.assertRegex(p.stdout, r"box: \d+ points, \d+ tetrahedra")
        cad = re.search(r"Solid1: CAD volume ([0-9.e+-]+), mesh ([0-9.e+-]+)", p.stdout)
        self.assertTrue(cad, p.stdout)
        self.assertAlmostEqual(float(cad.group(1)), 3 * 3.141592653589793, places=4)
        # The files the program wrote, measured by the installed vdmesh
        # command: the box's volume exactly, the cylinder's within 0.5 %.
        for out, volume, tolerance in ((box_out, 1.0, 1e-9), (part_out, float(cad.group(1)), 0.005)):
            q = subprocess.run([self.bin, "info", out], capture_output=True, text=True, timeout=60)
            self.assertEqual(q.returncode, 0, q.stderr)
            measured = re.search(r"region 1: volume ([0-9.e+-]+)", q.stdout)
            self.assertTrue(measured, q.stdout)
            self.assertLess(abs(float(measured.group(1)) / volume - 1), tolerance, (out, q.stdout))
        with open(part_out) as f:
            deck = f.read()
        self.assertIn("ELSET=Solid1", deck)
        self.assertRegex(deck, r"\*SURFACE, NAME=Face1")

    def test_module_imports_from_the_site_dir(self):
        modules = [f for f in os.listdir(self.pydir) if f.startswith("vdmesh.") and f.endswith(".so")]
        self.assertEqual(len(modules), 1, os.listdir(self.pydir))
        code = ("import vdmesh, numpy as np\nprint(vdmesh.__file__)\n"
                "m = vdmesh.Mesh(points=np.eye(3), triangles=[[0, 1, 2]])\nprint(len(m.triangles))\n")
        env = dict(ENV, PYTHONPATH=self.pydir)
        p = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=60,
                           cwd=self.destdir)
        self.assertEqual(p.returncode, 0, p.stderr)
        where, count = p.stdout.split()
        self.assertEqual(os.path.dirname(where), self.pydir)
        self.assertEqual(count, "1")

    def test_workbench_is_a_copy_of_mod_vdmesh(self):
        source = os.path.join(ENV["VDMESH_SOURCE_DIR"], "Mod", "VDMesh")
        for name in ("Init.py", "InitGui.py"):
            self.assertTrue(os.path.isfile(os.path.join(self.mod, name)), name)
        for root, dirs, files in os.walk(source):
            dirs[:] = [d for d in dirs if d != "__pycache__"]
            for f in files:
                if f.endswith(".pyc"):
                    continue
                src = os.path.join(root, f)
                dst = os.path.join(self.mod, os.path.relpath(src, source))
                self.assertTrue(os.path.isfile(dst), dst)
                self.assertTrue(filecmp.cmp(src, dst, shallow=False), dst)
        for root, dirs, files in os.walk(self.mod):
            self.assertNotIn("__pycache__", dirs)


if __name__ == "__main__":
    unittest.main(verbosity=2)
