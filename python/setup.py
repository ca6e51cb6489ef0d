"""Build hook: the version is CMakeLists.txt's project(VERSION), aalab's one version; the
package ships the daemon's JSON Schemas (proto/schemas, the one source) as
package data, copied at build time so that no second copy is committed. Everything else is in
pyproject.toml."""

import os
import re
import shutil

from setuptools import setup
from setuptools.command.build_py import build_py

HERE = os.path.dirname(os.path.abspath(__file__))
SCHEMAS = os.path.join(HERE, "..", "proto", "schemas")
CMAKELISTS = os.path.join(HERE, "..", "CMakeLists.txt")


def aalab_version() -> str:
    """aalab's one version: project(aalab VERSION x.y.z) of the repository's CMakeLists.txt. An
    sdist built from the repository carries it in PKG-INFO."""
    pkg_info = os.path.join(HERE, "PKG-INFO")
    for path, pattern in ((CMAKELISTS, r"^project\(aalab VERSION ([0-9.]+)"),
                          (pkg_info, r"^Version: (\S+)")):
        if os.path.isfile(path):
            m = re.search(pattern, open(path, encoding="utf-8").read(), re.M)
            if m:
                return m.group(1)
    raise RuntimeError("no aalab version: build from the repository (../CMakeLists.txt)")


class build_py_with_schemas(build_py):
    def run(self) -> None:
        super().run()
        if not os.path.isdir(SCHEMAS):
            # Building from an sdist or a copy without the repository around it: the package
            # then falls back to AALAB_SCHEMA_DIR or works without schemas (aalab.schemas).
            return
        target = os.path.join(self.build_lib, "aalab", "schemas")
        shutil.rmtree(target, ignore_errors=True)
        shutil.copytree(SCHEMAS, target)


setup(version=aalab_version(), cmdclass={"build_py": build_py_with_schemas})
