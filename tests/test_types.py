"""Types: mypy over every module of the package as it is installed, with pyproject.toml's
[tool.mypy] (no error; the third-party modules without type information are listed there
with why). The domain folders (fea/, geometry/, loads/, kinematics/) are installed inside
the railcheck namespace, a layout mypy cannot see from the source tree, so the test lays
it out with links, as setuptools' strict editable mode does."""

import importlib.util
import subprocess
import sys

import pytest

from helpers import ROOT, package_dirs


def installed_layout(site) -> None:
    """``site``/railcheck/...: a link to every module of every package, where pip puts it."""
    for package, folder in package_dirs().items():
        target = site.joinpath(*package.split("."))
        target.mkdir(parents=True, exist_ok=True)
        for path in folder.glob("*.py"):
            (target / path.name).symlink_to(path)


def test_the_layout_holds_every_module_where_it_is_installed(tmp_path):
    installed_layout(tmp_path)
    assert (tmp_path / "railcheck" / "fea" / "screening" / "groups.py").resolve() == ROOT / "fea" / "screening" / "groups.py"
    assert (tmp_path / "railcheck" / "model" / "cycle.py").is_file()
    assert not (tmp_path / "fea").exists()


@pytest.mark.slow  # 28 s from an empty cache: mypy over 127 modules
@pytest.mark.skipif(importlib.util.find_spec("mypy") is None, reason="mypy is in the [test] extra")
def test_mypy_finds_no_error_in_the_installed_package(tmp_path):
    site = tmp_path / "site"
    installed_layout(site)
    cmd = [sys.executable, "-m", "mypy", "-p", "railcheck", "--config-file", str(ROOT / "pyproject.toml")]
    cmd += ["--cache-dir", str(tmp_path / "cache")]
    done = subprocess.run(cmd, cwd=site, capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "no issues found" in done.stdout
