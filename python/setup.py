"""Build hook: the package ships the daemon's JSON Schemas (proto/schemas, the one source) as
package data, copied at build time so that no second copy is committed. Everything else is in
pyproject.toml."""

import os
import shutil

from setuptools import setup
from setuptools.command.build_py import build_py

HERE = os.path.dirname(os.path.abspath(__file__))
SCHEMAS = os.path.join(HERE, "..", "proto", "schemas")


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


setup(cmdclass={"build_py": build_py_with_schemas})
