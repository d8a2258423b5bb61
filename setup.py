"""Ships the shared library inside the Python package: `pip install .
--no-build-isolation` (offline) copies build/librailride.so, building it with
CMake first when the tree has none ($RAILRIDE_LIB names another)."""
import os
import shutil
import subprocess

from setuptools import setup
from setuptools.command.build_py import build_py

HERE = os.path.dirname(os.path.abspath(__file__))


class build_with_library(build_py):
    def run(self):
        lib = os.environ.get("RAILRIDE_LIB") or os.path.join(HERE, "build", "librailride.so")
        if not os.path.exists(lib):
            subprocess.run(["cmake", "-S", HERE, "-B", os.path.join(HERE, "build")], check=True)
            subprocess.run(["cmake", "--build", os.path.join(HERE, "build"), "--target", "railride", "-j2"], check=True)
        super().run()
        dest = os.path.join(self.build_lib, "railride", "librailride.so")
        shutil.copyfile(os.path.realpath(lib), dest)


# setuptools' scratch goes under the CMake build tree, not into the sources
SCRATCH = os.path.join(HERE, "build", "python-package")
os.makedirs(SCRATCH, exist_ok=True)
setup(cmdclass={"build_py": build_with_library},
      options={"build": {"build_base": SCRATCH}, "egg_info": {"egg_base": SCRATCH}})
