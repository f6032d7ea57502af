"""`cmake --install` into a temporary DESTDIR: the program, the Python module
and the FreeCAD workbench land where the README says, and work from there.

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
