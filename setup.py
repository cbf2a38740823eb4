"""Builds the `simdbvh` Python module with the project's CMake (target
simdbvh_python) into the package folder; `pip install --no-build-isolation .`
uses Debian's setuptools, wheel, pybind11 and numpy, offline."""
import os
import pathlib
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        out = pathlib.Path(self.get_ext_fullpath(ext.name)).parent.resolve()
        out.mkdir(parents=True, exist_ok=True)
        build = pathlib.Path(self.build_temp).resolve() / "cmake"
        build.mkdir(parents=True, exist_ok=True)
        src = pathlib.Path(__file__).parent.resolve()
        subprocess.check_call(["cmake", "-S", str(src), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                               "-DSIMDBVH_BUILD_TESTS=OFF", "-DSIMDBVH_BUILD_BENCH=OFF", "-DSIMDBVH_PYTHON=ON",
                               f"-DSIMDBVH_PYTHON_EXECUTABLE={sys.executable}",
                               f"-DSIMDBVH_PYTHON_OUTPUT_DIR={out}"])
        subprocess.check_call(["cmake", "--build", str(build), "--target", "simdbvh_python",
                               "-j", str(os.cpu_count() or 1)])


setup(packages=["simdbvh"], package_dir={"": "python"},
      package_data={"simdbvh": ["__init__.pyi", "py.typed"]},
      ext_modules=[CMakeExtension("simdbvh._simdbvh")], cmdclass={"build_ext": CMakeBuild}, zip_safe=False)
