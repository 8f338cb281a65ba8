"""pytest plugin of ``benchmarks/mutation.py``: replaces one module of railcheck by a
mutant for the whole test session, without touching the installed files.

``RAILCHECK_MUTANT_MODULE`` names the module (e.g. ``railcheck.fea.fatigue``) and
``RAILCHECK_MUTANT_SOURCE`` the file holding the mutant's source. The finder sits first on
``sys.meta_path`` from the moment pytest loads this plugin (``-p mutation_plugin``), before
any test module imports railcheck. Child processes a test starts import the original.
"""

from __future__ import annotations

import importlib.abc
import importlib.util
import os
import sys


class _MutantLoader(importlib.abc.Loader):
    def __init__(self, source: str, origin: str):
        self.source, self.origin = source, origin

    def create_module(self, spec):
        return None  # the default module object

    def exec_module(self, module) -> None:
        module.__file__ = self.origin
        exec(compile(self.source, self.origin, "exec"), module.__dict__)


class _MutantFinder(importlib.abc.MetaPathFinder):
    def __init__(self, name: str, source: str, origin: str):
        self.name, self.loader = name, _MutantLoader(source, origin)

    def find_spec(self, fullname, path=None, target=None):
        if fullname != self.name:
            return None
        return importlib.util.spec_from_loader(fullname, self.loader, origin=self.loader.origin)


def _install() -> None:
    name, path = os.environ.get("RAILCHECK_MUTANT_MODULE"), os.environ.get("RAILCHECK_MUTANT_SOURCE")
    if not name or not path:
        return
    if name in sys.modules:
        raise RuntimeError(f"{name} was imported before the mutant could replace it")
    with open(path, encoding="utf-8") as f:
        source = f.read()
    sys.meta_path.insert(0, _MutantFinder(name, source, os.environ.get("RAILCHECK_MUTANT_ORIGIN", path)))


_install()
