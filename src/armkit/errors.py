"""Exceptions raised by armkit.

Every error a user can cause derives from :class:`ArmkitError` and also from the
matching builtin, so ``except ValueError`` keeps working for generic code.
"""

from __future__ import annotations

from ._text import Fielded

__all__ = [
    "ArmkitError",
    "ArgumentError",
    "ShapeError",
    "NotRigidError",
    "RobotDefinitionError",
    "RobotFileError",
    "UnknownRobotError",
    "RobotFileNotFoundError",
    "JointLimitError",
    "UnreachableError",
    "WriteError",
    "WriteInterrupted",
    "LimitError",
    "IKInputError",
    "ParseError",
    "MissingExtraError",
    "SceneError",
    "SceneFileError",
    "SceneNotSupportedError",
    "ReachabilityError",
    "MapFileError",
    "ViewError",
    "CalibrationRangeWarning",
    "CalibrationInputError",
]


class ArmkitError(Exception):
    """Base class of every armkit error.

    An error built by :meth:`of` carries its message as a template and fields (``.template``, ``.fields``),
    so a front end renders it in the user's language from the catalogue (:func:`armkit.locale.library.localize`)
    instead of reading the English back.
    """

    @classmethod
    def of(cls, template: str, /, **fields: object) -> "ArmkitError":
        """The error whose message is ``template.format(**fields)``, keeping both: ``ShapeError.of("got {n}", n=3)``."""
        exc = cls(template.format(**fields))
        exc.template, exc.fields = template, fields  # type: ignore[attr-defined]
        return exc


class ArgumentError(ArmkitError, ValueError):
    """An argument has a value the function cannot use (an unknown option, a non-positive count, ...).

    The message names the argument, the valid values and what was given:
    ``frame must be 'base' or 'tool', got 'world'``.
    """


class ShapeError(ArmkitError, ValueError):
    """An array argument has the wrong shape or holds non-finite values."""


class NotRigidError(ShapeError):
    """A 4x4 matrix given as a pose is not a rigid transform (``R^T R != I``, ``det R != 1`` or a last row
    other than (0, 0, 0, 1)); the message says by how much. A :class:`ShapeError` (so a ``ValueError``), as
    every malformed pose argument is."""


class RobotDefinitionError(ArmkitError, ValueError):
    """A robot description is inconsistent (NaN parameter, lower limit > upper, no joints, ...)."""


class RobotFileError(RobotDefinitionError):
    """A robot file is malformed; the message names the file, the line and the field."""

    def __init__(self, path: str, message: str, line: int | None = None, field: str | None = None, /,
                 **fields: object):
        # positional only: a message's own fields may be called path, line or field (a mesh's path)
        self.path = str(path)
        self.line = line
        self.field = field
        location = self.path if line is None else f"{self.path}:{line}"
        where: str = location
        if field and getattr(field, "template", None):      # a field in words (joint 'x'): its own template
            where = Fielded.of("{location}: {field}", location=location, field=field)
        elif field:
            where += f": {field}"
        # with fields, ``message`` is a template: ``.template`` and ``.fields`` render it in any language
        self.template = "{where}: " + (message if fields else message.replace("{", "{{").replace("}", "}}"))
        self.fields = {**fields, "where": where}
        super().__init__(f"{where}: {message.format(**fields) if fields else message}")

    @classmethod
    def wrap(cls, path: str, exc: BaseException, line: int | None = None,
             field: str | None = None) -> "RobotFileError":
        """The file's error for ``exc`` (an error of the model raised while the file was read), keeping the
        template and fields ``exc`` was built from, if any."""
        template, fields = getattr(exc, "template", None), getattr(exc, "fields", None)
        if isinstance(template, str) and isinstance(fields, dict):      # rendered as a part: "{where}: {error}"
            return cls(path, "{error}", line, field, error=exc)
        return cls(path, str(exc), line, field)


class UnknownRobotError(ArmkitError, KeyError):
    """A robot name is neither bundled nor an existing file."""

    def __init__(self, name: str, valid: list[str]):
        self.name = name
        self.valid = list(valid)
        super().__init__(name)

        self.template = ("unknown robot {name!r}; bundled robots are: {names} (or give the path of a .toml or "
                         ".urdf robot file)")
        self.fields: dict[str, object] = {"name": name, "names": ", ".join(self.valid)}

    def __str__(self) -> str:  # KeyError would quote the whole message
        return self.template.format(**self.fields)


class RobotFileNotFoundError(UnknownRobotError):
    """A robot name that is a path (it has a ``/`` or a robot file's suffix) names no file: ``PATH: file not found``."""

    def __init__(self, path: str):
        super().__init__(path, [])
        self.template, self.fields = "{path}: file not found", {"path": path}


class JointLimitError(ArmkitError, ValueError):
    """A joint value lies outside its limits (raised only in strict mode)."""


class UnreachableError(ArmkitError, ValueError):
    """An IK target cannot be reached; the message says how far outside it lies."""


class WriteError(ArmkitError, OSError):
    """An output file cannot be written; the message is ``cannot write PATH: reason``.

    Nothing is left behind: armkit writes to a temporary file next to ``PATH`` and renames
    it into place only when the whole file is written.
    """

    def __init__(self, path: object, reason: str, /, **fields: object):
        self.path = str(path)
        self.reason = reason.format(**fields) if fields else reason
        # with fields, ``reason`` is a template (``.template``, ``.fields``: the message in any language)
        self.template = "cannot write {path}: " + (reason if fields else reason.replace("{", "{{").replace("}", "}}"))
        self.fields = {**fields, "path": self.path}
        super().__init__(f"cannot write {self.path}: {self.reason}")

    def __str__(self) -> str:  # OSError would format (errno, strerror)
        return f"cannot write {self.path}: {self.reason}"


class WriteInterrupted(KeyboardInterrupt):
    """Ctrl-C arrived while a file was written; the temporary file was removed, the old file is intact."""

    def __init__(self, path: object):
        self.path = str(path)
        super().__init__(f"interrupted; {self.path} not written")

    def __str__(self) -> str:
        return f"interrupted; {self.path} not written"


class LimitError(ArmkitError, ValueError):
    """A request too large to finish (memory or sample count); the message gives the limit and how to raise it."""


class IKInputError(ArgumentError):
    """An IK argument that cannot work: unknown method or branch, a closed form asked of an arm without one, ..."""


class ParseError(ArgumentError):
    """A statement the interactive shell cannot use; its text is the one-line message."""


class MissingExtraError(ArmkitError, ImportError):
    """An optional dependency is not installed; the message names the pip extra that brings it.

    ``armkit view needs the 'view' extra (No module named 'viser'): pip install 'armkit[view]'``
    """

    def __init__(self, what: str, extra: str, module: str, reason: str = ""):
        self.what = what
        self.extra = extra
        self.module = module
        self.template = ("{what} needs the {extra} extra ({reason}): {command}" if reason else
                         "{what} needs the {extra} extra: {command}")
        self.fields = {"what": what, "extra": repr(extra), "reason": reason, "command": f"pip install 'armkit[{extra}]'"}
        super().__init__(self.template.format(**self.fields), name=module)


class SceneError(ArmkitError, ValueError):
    """A shape or scene that cannot work: a negative radius, a zero normal, an unknown unit, ..."""


class SceneFileError(RobotFileError):
    """A malformed scene file: the message names the file, line and field (exit code 2 in the CLI)."""


class SceneNotSupportedError(ArmkitError, NotImplementedError):
    """``scene=`` was given but this build of armkit has no collision checking."""


class ReachabilityError(ArmkitError, ValueError):
    """A bad argument to :func:`armkit.reachability` or a store that does not match the build."""


class MapFileError(ArmkitError, ValueError):
    """A path that is not a readable armkit reachability map (or not a finished one)."""


class ViewError(ArmkitError, ValueError):
    """A view that cannot start or a bad argument to the handle (port in use, bad host, ...).

    Built from a template and its fields (``ViewError("got {value!r}", value=v)``), the page shows it in
    its own language (``translate(e.template, lang, **e.fields)``); without fields the text is the message.
    """

    def __init__(self, message: str = "", /, **fields: object):
        super().__init__(message.format(**fields) if fields else message)
        self.template, self.fields = message, fields


class CalibrationInputError(ArgumentError):
    """A bad LeRobot calibration file or servo reading (:mod:`armkit.lerobot`), built from a template and its
    fields, so that a front end shows it in the user's language (``_(e.template, **e.fields)``)."""

    def __init__(self, template: str, **fields: object):
        super().__init__(template.format(**fields))
        self.template, self.fields = template, fields


# ------------------------------------------------------------------ warnings (categories for warnings.warn)
def warning_of(template: str, /, category: type[Warning] = UserWarning, **fields: object) -> Warning:
    """A warning whose text is ``template.format(**fields)``, keeping both (``.template``, ``.fields``) so that a
    front end shows it in the user's language: ``warnings.warn(warning_of("{n} files", n=2))``."""
    w = category(template.format(**fields))
    w.template, w.fields = template, fields  # type: ignore[attr-defined]
    return w


class CalibrationRangeWarning(UserWarning):
    """A servo reading (or joint angle) outside a motor's calibrated range ``[range_min, range_max]``
    (:mod:`armkit.lerobot`): mapped as LeRobot maps it, and said once per call."""
