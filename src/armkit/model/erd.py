"""Robot names that :func:`armkit.load` resolves before it looks for a file.

``example-robot-data:NAME``
    A URDF arm of the `example-robot-data <https://github.com/Gepetto/example-robot-data>`_ package
    (``pip install 'armkit[robots]'``; ``make test`` installs it): ``example-robot-data:ur5`` is
    ``ur_description/urdf/ur5_robot.urdf`` with the tip ``tool0``, the arms of :data:`ROBOTS` likewise.
    ``example-robot-data:PATH`` (a path inside the package's ``robots`` folder, ending in ``.urdf``)
    loads any other file of it.

A name that looks like a path (it has a ``/`` or ends in ``.toml``, ``.urdf`` or ``.xml``) and names no file
raises :class:`armkit.errors.RobotFileNotFoundError` (``PATH: file not found``), not "unknown robot".

>>> sorted(ROBOTS)[:3]
['kinova', 'panda', 'so101']
"""

from __future__ import annotations

import site
import sys
import sysconfig
from pathlib import Path

from ..errors import ArgumentError, MissingExtraError, RobotFileNotFoundError

__all__ = ["PREFIX", "ROBOTS", "robots_folder", "resolve"]

PREFIX = "example-robot-data:"

ROBOTS: dict[str, tuple[str, str | None, str | None]] = {
    # name: (file under the package's robots/ folder, base link, tip link); None: the loader's default
    "ur3": ("ur_description/urdf/ur3_robot.urdf", None, "tool0"),
    "ur5": ("ur_description/urdf/ur5_robot.urdf", None, "tool0"),
    "ur10": ("ur_description/urdf/ur10_robot.urdf", None, "tool0"),
    "panda": ("panda_description/urdf/panda.urdf", None, "panda_hand_tcp"),
    "kinova": ("kinova_description/robots/kinova.urdf", None, "j2s6s200_end_effector"),
    "z1": ("z1_description/urdf/z1.urdf", None, None),
    "so101": ("so_arm_description/urdf/so101.urdf", "base_link", "gripper_frame_link"),
    "xarm7": ("xarm_description/urdf/xarm7.urdf", None, "link_eef"),
    "talos": ("talos_data/robots/talos_reduced.urdf", "torso_2_link", "gripper_left_base_link"),   # left arm
    "tiago": ("tiago_description/robots/tiago.urdf", "torso_lift_link", "arm_tool_link"),   # arm above the lift
}
"""The arms ``example-robot-data:NAME`` knows by name (any other file: ``example-robot-data:PATH.urdf``)."""

_PATH_SUFFIXES = (".toml", ".urdf", ".xml")


def robots_folder() -> Path | None:
    """The ``robots`` folder of the installed example-robot-data package (a cmeel wheel), or None."""
    tail = Path("cmeel.prefix") / "share" / "example-robot-data" / "robots"
    places = [sysconfig.get_paths().get("purelib"), sysconfig.get_paths().get("platlib")]
    try:
        places += site.getsitepackages() + [site.getusersitepackages()]
    except AttributeError:  # pragma: no cover  (a virtualenv's old site module)
        pass
    places.append(str(Path(sys.prefix) / "lib" / f"python{sys.version_info[0]}.{sys.version_info[1]}"
                      / "site-packages"))
    for place in places:
        if place and (Path(place) / tail).is_dir():
            return Path(place) / tail
    try:   # installed somewhere else: ask the package's own record
        from importlib.metadata import PackageNotFoundError, distribution

        for f in distribution("example-robot-data").files or ():
            text = str(f).replace("\\", "/")
            if "/share/example-robot-data/robots/" in text:
                found = Path(str(f.locate()))
                while found.name != "robots":
                    found = found.parent
                return found if found.is_dir() else None
    except (PackageNotFoundError, OSError):
        pass
    return None


def resolve(name_or_path: str | Path, base: str | None,
            tip: str | None) -> tuple[str | Path, str | None, str | None]:
    """``(name_or_path, base, tip)`` with an ``example-robot-data:`` name turned into its file and chain.

    Raises
    ------
    MissingExtraError
        ``example-robot-data:...`` without the package installed (the message names the ``robots`` extra).
    ArgumentError
        ``example-robot-data:NAME`` with a NAME it does not know (the message lists the known ones).
    RobotFileNotFoundError
        A path (it has a ``/`` or a robot file's suffix) that names no file.
    """
    if isinstance(name_or_path, str) and name_or_path.startswith(PREFIX):
        what = name_or_path[len(PREFIX):].strip()
        folder = robots_folder()
        if folder is None:
            raise MissingExtraError(name_or_path, "robots", "example_robot_data")   # the package is not installed
        if what in ROBOTS:
            file, default_base, default_tip = ROBOTS[what]
            return (str(folder / file), base if base is not None else default_base,
                    tip if tip is not None else default_tip)
        if what.lower().endswith((".urdf", ".xml")) and ".." not in Path(what).parts:
            path = folder / what
            if not path.is_file():
                raise RobotFileNotFoundError(name_or_path)
            return str(path), base, tip
        raise ArgumentError.of("unknown arm {name!r} of example-robot-data; known arms: {names} (or "
                               "example-robot-data:PATH.urdf, a file of its robots folder)", name=what,
                               names=", ".join(sorted(ROBOTS)))
    if isinstance(name_or_path, (str, Path)) and _looks_like_path(name_or_path) and not _exists(name_or_path):
        raise RobotFileNotFoundError(str(name_or_path))
    return name_or_path, base, tip


def _looks_like_path(name: str | Path) -> bool:
    if isinstance(name, Path):
        return True
    return "/" in name or "\\" in name or name.lower().endswith(_PATH_SUFFIXES)


def _exists(name: str | Path) -> bool:
    try:
        return Path(name).exists()
    except (OSError, ValueError):   # a name the system cannot look up (too long, a NUL byte): not a file
        return False
