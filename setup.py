"""Installed, the repository's folders are ONE package, `soccer_lab`: `fuzzy/` is `soccer_lab.fuzzy`, `app/` is
`soccer_lab.app`, and so on, so that no generic top-level name (`app`, `fuzzy`, ...) lands in site-packages and
the package index's `fuzzy` installs beside it. The folder `soccer_lab/` holds the package itself (the Python
API). pyproject.toml holds everything else; this file only maps the folders into the one namespace (a mapping
pyproject.toml cannot compute)."""

from setuptools import find_namespace_packages, setup

FOLDERS = ("fuzzy", "ga", "soccer", "app", "static")  # each is soccer_lab.<folder> once installed

setup(
    package_dir={"soccer_lab": "soccer_lab", **{f"soccer_lab.{folder}": folder for folder in FOLDERS}},
    packages=["soccer_lab", *(f"soccer_lab.{package}" for package in find_namespace_packages(
        include=[pattern for folder in FOLDERS for pattern in (folder, f"{folder}.*")]))],
)
