"""Builds the `simdbvh` Python module with the project's CMake (target
simdbvh_python) into the package folder; `pip install --no-build-isolation .`
uses Debian's setuptools, wheel, pybind11 and numpy, offline.

SIMDBVH_CMAKE_BUILD_DIR (optional, for CI): an existing, configured CMake build
tree of this source (Release, SIMDBVH_PYTHON=ON, e.g. build/release after the
README's test command). setup.py then builds simdbvh_python there (a no-op when
it is up to date) and packages that module instead of configuring and compiling
a second tree. Without it (what users run), a fresh tree under setuptools'
build_temp is configured and built as before."""
import os
import pathlib
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


def _cache(build):
    """The CMakeCache.txt entries of a build tree, name -> value."""
    entries = {}
    for line in (build / "CMakeCache.txt").read_text().splitlines():
        if line and not line.startswith(("#", "//")) and "=" in line:
            key, value = line.split("=", 1)
            entries[key.split(":", 1)[0]] = value
    return entries


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        target = pathlib.Path(self.get_ext_fullpath(ext.name)).resolve()
        out = target.parent
        out.mkdir(parents=True, exist_ok=True)
        src = pathlib.Path(__file__).parent.resolve()
        existing = os.environ.get("SIMDBVH_CMAKE_BUILD_DIR")
        if existing:
            self._from_existing_tree(src, (src / existing).resolve(), target)
            return
        build = pathlib.Path(self.build_temp).resolve() / "cmake"
        build.mkdir(parents=True, exist_ok=True)
        subprocess.check_call(["cmake", "-S", str(src), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                               "-DSIMDBVH_BUILD_TESTS=OFF", "-DSIMDBVH_BUILD_BENCH=OFF", "-DSIMDBVH_PYTHON=ON",
                               f"-DSIMDBVH_PYTHON_EXECUTABLE={sys.executable}",
                               f"-DSIMDBVH_PYTHON_OUTPUT_DIR={out}"])
        subprocess.check_call(["cmake", "--build", str(build), "--target", "simdbvh_python",
                               "-j", str(os.cpu_count() or 1)])

    def _from_existing_tree(self, src, build, target):
        """SIMDBVH_CMAKE_BUILD_DIR: build simdbvh_python in that tree and copy it to `target`."""
        if not (build / "CMakeCache.txt").is_file():
            sys.exit(f"setup.py: SIMDBVH_CMAKE_BUILD_DIR={build} is not a configured CMake build tree")
        cache = _cache(build)
        problems = []
        if pathlib.Path(cache.get("CMAKE_HOME_DIRECTORY", "")).resolve() != src:
            problems.append(f"its source is {cache.get('CMAKE_HOME_DIRECTORY')}, not {src}")
        if cache.get("CMAKE_BUILD_TYPE") != "Release":
            problems.append(f"CMAKE_BUILD_TYPE is '{cache.get('CMAKE_BUILD_TYPE')}', not Release")
        if cache.get("SIMDBVH_PYTHON", "").upper() not in ("ON", "TRUE", "1", "YES"):
            problems.append("SIMDBVH_PYTHON is not ON")
        # A fresh configure takes these from CXXFLAGS / LDFLAGS (empty unless set).
        for flags, env in (("CMAKE_CXX_FLAGS", "CXXFLAGS"), ("CMAKE_MODULE_LINKER_FLAGS", "LDFLAGS")):
            if cache.get(flags, "").split() != os.environ.get(env, "").split():
                problems.append(f"{flags} is '{cache.get(flags)}', a fresh configure's would be "
                                f"'{os.environ.get(env, '')}' (${env})")
        if problems:
            sys.exit(f"setup.py: SIMDBVH_CMAKE_BUILD_DIR={build}: " + "; ".join(problems))
        subprocess.check_call(["cmake", "--build", str(build), "--target", "simdbvh_python",
                               "-j", str(os.cpu_count() or 1)])
        pkg = pathlib.Path(cache.get("SIMDBVH_PYTHON_OUTPUT_DIR") or build / "python" / "simdbvh")
        built = pkg / target.name  # same name only if the tree's interpreter has this one's ABI suffix
        if not built.is_file():
            found = sorted(p.name for p in pkg.glob("_simdbvh*"))
            sys.exit(f"setup.py: {built} not found after the build (found {found}): "
                     f"the tree's Python is not {sys.executable}'s ABI")
        print(f"setup.py: packaging {built} (SIMDBVH_CMAKE_BUILD_DIR)")
        shutil.copy2(built, target)


setup(packages=["simdbvh"], package_dir={"": "python"},
      package_data={"simdbvh": ["__init__.pyi", "py.typed"]},
      ext_modules=[CMakeExtension("simdbvh._simdbvh")], cmdclass={"build_ext": CMakeBuild}, zip_safe=False)
