"""The teaching readouts of the browser view: T and J, stored configurations, frames, camera presets.

What MATLAB's ``interactiveRigidBodyTree`` and the Robotics Toolbox teach panel show a class:

- **T and J.** The end frame's pose ``T = fk(robot, q)`` as a live 4x4 matrix in the robot's
  unit, and on demand the geometric Jacobian (:func:`armkit.jacobian`, world frame), each
  with a *Copy* button that puts the plain rows on the clipboard (the text is also the
  button's ``data-copy`` attribute).
- **Stored configurations.** Save the current ``q`` under a name, recall, rename, delete;
  export the list as TOML (a download and the text in the page) and import such a file.
  Each browser keeps its own list, in its ``localStorage`` (viser's
  ``ClientHandle.local_storage``): it comes back when the page is reloaded at the same
  address (host and port), and is never sent to another browser.
- **Frames.** A labelled world triad, the frame numbers ``{0} ... {n}`` of
  :func:`armkit.fk_frames` at each frame origin (frames that share an origin share a
  label), and on demand the DH frames: each frame's x axis (red) and z axis (blue).
- **Camera presets.** Front (from +x), side (from -y), top (from +z) and iso (from
  (1, -1, 1)), looking at the shoulder, far enough that the whole reach fits.
- **Colour bar** of the reach cloud (:func:`colour_bar_html`, used by the *Workspace* panel).

Every label comes from the gettext catalogue (English here, Korean in
``armkit/locale/ko``). Nothing typed in the page is evaluated: a stored name is text, an
imported file is read with :mod:`tomllib` and every value checked.
"""

from __future__ import annotations

import html
import json
import math
import re
import threading
from typing import TYPE_CHECKING, Any, Optional, Sequence

import numpy as np
from numpy.typing import NDArray

from ...errors import ArmkitError, ViewError
from ...kinematics import fk_frames, jacobian
from ...locale import N_, translate
from ...locale.library import localize
from ...model import Robot
from .drawing import wxyz_from_rotation

if TYPE_CHECKING:  # pragma: no cover
    from .server import View

__all__ = ["Readouts", "matrix_text", "matrix_html", "colour_bar_html", "configurations_toml",
           "parse_configurations_toml", "camera_preset", "frame_number_groups", "CAMERA_PRESETS",
           "STORAGE_KEY", "MAX_STORED"]

Array = NDArray[np.float64]

TEXTS: dict[str, str] = {     # English here, Korean in the catalogue (docs/languages.md)
    "readouts": N_("T and J"),
    "t_caption": N_("T: the end frame in the world ({unit})"),
    "show_j": N_("show J"),
    "j_caption": N_("J in the world frame, rows (v, ω): v in {unit}, ω in rad, per unit of each joint"),
    "copy": N_("Copy"),
    "copied": N_("✓ copied"),
    "stored": N_("Stored configurations"),
    "name": N_("name"),
    "save": N_("Save current"),
    "list": N_("stored"),
    "recall": N_("Recall"),
    "rename": N_("Rename"),
    "delete": N_("Delete"),
    "export": N_("Export TOML"),
    "import": N_("Import TOML"),
    "default_name": N_("pose {k}"),
    "saved": N_("saved {name!r}"),
    "replaced": N_("replaced {name!r}"),
    "recalled": N_("recalled {name!r}"),
    "renamed": N_("renamed {old!r} to {new!r}"),
    "deleted": N_("deleted {name!r}"),
    "name_taken": N_("a configuration named {name!r} exists; choose another name"),
    "nothing_chosen": N_("no stored configuration chosen"),
    "exported": N_("{k} configurations as TOML:"),
    "imported": N_("imported {k} configurations"),
    "full": N_("the list is full ({k} configurations); delete some first"),
    "kept_where": N_("kept in this browser for {address}"),
    "not_kept": N_("this browser does not keep the list ({why}); export it before closing the page"),
    "bad_stored": N_("the list kept in this browser could not be read and was left out: {why}"),
    "frames": N_("Frames and camera"),
    "world_triad": N_("world triad"),
    "frame_numbers": N_("frame numbers"),
    "dh_frames": N_("DH frames (x red, z blue)"),
    "camera": N_("camera"),
    "front": N_("front"),
    "side": N_("side"),
    "top": N_("top"),
    "iso": N_("iso"),
    "world": N_("world"),
    "colour_bar": N_("manipulability: dark is low; yellow is {top} or more (the top 1 %)"),
}

STORAGE_KEY = "armkit-configurations-{robot}"
"""The ``localStorage`` key of a robot's stored configurations (one list per robot and address)."""
MAX_STORED = 200               # stored configurations per browser and robot
MAX_NAME = 60                  # characters of a stored name
MAX_IMPORT_BYTES = 1_000_000   # an imported TOML file
CAMERA_PRESETS = ("front", "side", "top", "iso")
_DIRECTIONS = {"front": (1.0, 0.0, 0.0), "side": (0.0, -1.0, 0.0), "top": (0.0, -1e-3, 1.0),
               "iso": (1.0, -1.0, 1.0)}
X_COLOUR, Z_COLOUR = (220, 30, 30), (30, 70, 230)
_COPY_JS = ("(function(b){var t=b.getAttribute('data-copy');"
            "function ok(){b.setAttribute('data-copied','1');b.textContent=b.getAttribute('data-done');}"
            "function old(){var a=document.createElement('textarea');a.value=t;a.style.position='fixed';"
            "a.style.opacity='0';document.body.appendChild(a);a.select();"
            "try{if(document.execCommand('copy')){ok();}}catch(e){}document.body.removeChild(a);}"
            "if(navigator.clipboard&&window.isSecureContext){navigator.clipboard.writeText(t).then(ok,old);}"
            "else{old();}})(this)")
"""The copy button's click: the clipboard API (a secure context: localhost or https), else a hidden
textarea and ``execCommand('copy')`` (a page served to the network over http)."""


def _fmt(v: float, decimals: int) -> str:
    s = f"{v:.{decimals}f}"
    return s[1:] if s.startswith("-") and float(s) == 0.0 else s


def matrix_text(M: Any, decimals: Any) -> str:
    """Plain rows of a matrix, right-aligned columns separated by two spaces.

    Parameters
    ----------
    M : array_like, shape (r, c)
    decimals : array_like of int, broadcastable to (r, c)
        Decimals of each number: shape ``(c,)`` per column, ``(r, 1)`` per row.

    Returns
    -------
    str
        ``r`` lines; ``line.split()`` gives the numbers back.

    Examples
    --------
    >>> print(matrix_text([[1.0, -0.0], [0.25, 12.5]], [2, 1]))
    1.00   0.0
    0.25  12.5
    """
    A = np.asarray(M, dtype=float)
    D = np.broadcast_to(np.asarray(decimals, dtype=int), A.shape)
    cells = [[_fmt(float(A[i, j]), int(D[i, j])) for j in range(A.shape[1])] for i in range(A.shape[0])]
    widths = [max(len(cells[i][j]) for i in range(A.shape[0])) for j in range(A.shape[1])]
    return "\n".join("  ".join(c.rjust(w) for c, w in zip(row, widths)) for row in cells)


def matrix_html(M: Any, decimals: Any, css: str, copy: str, done: str,
                rows: Sequence[str] = (), columns: Sequence[str] = ()) -> str:
    """An HTML table of ``M`` between brackets, with a copy button carrying :func:`matrix_text`."""
    A = np.asarray(M, dtype=float)
    text = matrix_text(A, decimals)
    cell = 'style="text-align:right;padding:0 0.35em;white-space:nowrap"'
    head = ""
    if columns:
        head = ("<tr>" + ("<td></td>" if rows else "")
                + "".join(f'<td {cell}><i>{html.escape(c)}</i></td>' for c in columns) + "</tr>")
    body = []
    for i, line in enumerate(text.splitlines()):
        lab = f'<td {cell}><i>{html.escape(rows[i])}</i></td>' if rows else ""
        body.append("<tr>" + lab + "".join(f'<td class="armkit-num" {cell}>{v}</td>' for v in line.split()) + "</tr>")
    return (f'<div style="padding:0 0.5em;font-size:0.8em"><table class="armkit-matrix {css}" '
            f'style="font-family:monospace;border-collapse:collapse;border-left:1px solid currentColor;'
            f'border-right:1px solid currentColor;margin:0.2em 0">{head}{"".join(body)}</table>'
            f'<button type="button" class="armkit-copy {css}-copy" data-copy="{html.escape(text)}" '
            f'data-done="{html.escape(done)}" onclick="{html.escape(_COPY_JS)}" '
            f'style="font-size:0.9em;padding:0.1em 0.6em;cursor:pointer">{html.escape(copy)}</button></div>')


def colour_bar_html(top: float, lang: str = "en") -> str:
    """A viridis colour bar from 0 to ``top`` (the value shown in yellow), for the reach cloud.

    The stops are matplotlib's ``viridis`` (the colours of the cloud's points).
    """
    from matplotlib import colormaps

    stops = ", ".join(
        "rgb({}, {}, {}) {:.0f}%".format(*(int(round(255 * c)) for c in colormaps["viridis"](x)[:3]), 100 * x)
        for x in np.linspace(0.0, 1.0, 9))
    caption = translate(TEXTS["colour_bar"], lang, top=f"{top:.3g}")
    return (f'<div class="armkit-colour-bar" data-top="{top!r}" style="padding:0.2em 0.5em;font-size:0.8em">'
            f'<div class="armkit-colour-bar-gradient" style="height:0.9em;border-radius:2px;'
            f'background:linear-gradient(to right, {stops})"></div>'
            f'<div style="display:flex;justify-content:space-between"><span>0</span>'
            f'<span>{html.escape(f"{top:.3g}")}</span></div>'
            f'<div style="word-break:keep-all">{html.escape(caption)}</div></div>')


def frame_number_groups(F: Array, tol: float) -> list[tuple[int, str]]:
    """Frames that share an origin share a label: ``[(frame, "{3} {4} {5}"), ...]``.

    Parameters
    ----------
    F : ndarray, shape (n + 1, 4, 4)
        :func:`armkit.fk_frames` of one configuration.
    tol : float
        Origins closer than this are one place.

    Examples
    --------
    >>> F = np.tile(np.eye(4), (3, 1, 1)); F[1, 0, 3] = 1.0
    >>> frame_number_groups(F, 1e-9)
    [(0, '{0} {2}'), (1, '{1}')]
    """
    firsts: list[int] = []
    groups: dict[int, list[int]] = {}
    for k in range(len(F)):
        for f in firsts:
            if float(np.linalg.norm(F[k, :3, 3] - F[f, :3, 3])) <= tol:
                groups[f].append(k)
                break
        else:
            firsts.append(k)
            groups[k] = [k]
    return [(f, " ".join(f"{{{k}}}" for k in groups[f])) for f in firsts]


def camera_preset(robot: Robot, name: str, fov: float = math.radians(50.0)) -> tuple[Array, Array]:
    """Camera ``(position, look_at)`` in metres for a preset, the up direction being +z.

    Parameters
    ----------
    robot : Robot
    name : {"front", "side", "top", "iso"}
        From +x, from -y, from +z (tilted by 1e-3 so that +y is up on the screen), from (1, -1, 1).
    fov : float
        The camera's vertical field of view (rad); the distance makes a sphere of the robot's
        reach around the shoulder fit it.

    Returns
    -------
    position, look_at : ndarray, shape (3,)
    """
    from ...analysis.workspace import shoulder_point

    if name not in _DIRECTIONS:
        raise ViewError(N_("camera preset must be one of {names}, got {name!r}"), names=", ".join(CAMERA_PRESETS), name=name)
    s = robot.unit_scale
    centre = np.asarray(shoulder_point(robot), dtype=float) * s
    R = (robot.reach or 1.0) * s
    half = 0.5 * (fov if math.isfinite(fov) and 0.05 < fov < 3.0 else math.radians(50.0))
    d = np.asarray(_DIRECTIONS[name], dtype=float)
    distance = 1.1 * R / math.sin(half)
    return centre + distance * d / np.linalg.norm(d), centre


# ---------------------------------------------------------------------- stored configurations: TOML
def _joint_scale(robot: Robot) -> Array:
    """Per joint: degrees per radian for a revolute joint, 1 for a prismatic one (the file's units)."""
    return np.array([1.0 if j.is_prismatic else 180.0 / math.pi for j in robot.joints])


def configurations_toml(robot: Robot, entries: Sequence[tuple[str, Any]]) -> str:
    """The TOML text of stored configurations: revolute joints in degrees, prismatic in ``robot.unit``.

    Parameters
    ----------
    robot : Robot
    entries : sequence of (str, array_like shape (n,))
        Names and joint vectors (rad / robot unit).

    Returns
    -------
    str
        ``robot``, ``unit``, ``angle_unit = "deg"``, ``joints`` and one ``[[configuration]]``
        table (``name``, ``q``) per entry, values to 12 significant digits (30.0, not
        29.999999999999996); :func:`parse_configurations_toml` reads it back.
    """
    import tomli_w

    k = _joint_scale(robot)
    data = {"robot": robot.name, "unit": robot.unit, "angle_unit": "deg", "joints": list(robot.joint_names),
            "configuration": [{"name": str(name), "q": [float(f"{v:.12g}") for v in np.asarray(q, dtype=float) * k]}
                              for name, q in entries]}
    return "# armkit stored configurations (armkit view)\n" + str(tomli_w.dumps(data))


def _clean_name(name: Any) -> str:
    text = re.sub(r"[\x00-\x1f\x7f]+", " ", str(name)).strip()
    return text[:MAX_NAME]


def _checked_entry(robot: Robot, name: Any, q: Any, where: int) -> tuple[str, Array]:
    if not isinstance(name, str) or not _clean_name(name):
        raise ViewError(N_("configuration {k}: the name must be a non-empty text, got {name!r}"), k=where, name=name)
    if not isinstance(q, list) or len(q) != robot.n or not all(
            isinstance(v, (int, float)) and not isinstance(v, bool) for v in q):
        raise ViewError(N_("configuration {k}: q must be a list of {n} numbers for robot {robot!r}, got {q}"), k=where,
                        n=robot.n, robot=robot.name, q=repr(q)[:200])
    arr = np.array(q, dtype=float)
    if not np.all(np.isfinite(arr)):
        raise ViewError(N_("configuration {k}: q must be finite numbers, got {q}"), k=where, q=repr(q)[:200])
    return _clean_name(name), arr


def parse_configurations_toml(robot: Robot, text: str) -> list[tuple[str, Array]]:
    """Read :func:`configurations_toml` text back: ``[(name, q), ...]``, ``q`` in rad / robot unit.

    Raises
    ------
    ViewError
        Not TOML, another robot's joints, another unit, a bad value, or a ``q`` outside the
        joint limits (the message names the configuration).
    """
    import tomllib

    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ViewError(N_("not a TOML file: {why}"), why=str(exc)) from exc
    joints = data.get("joints")
    if joints is not None and list(joints) != list(robot.joint_names):
        raise ViewError(N_("the file's joints {joints} are not the joints of robot {robot!r} ({names})"),
                        joints=repr(joints)[:200], robot=robot.name, names=", ".join(robot.joint_names))
    unit = data.get("unit", robot.unit)
    if unit != robot.unit:
        raise ViewError(N_("the unit must be {unit!r} for robot {robot!r}, got {got}"), unit=robot.unit, robot=robot.name,
                        got=repr(unit)[:100])
    angle_unit = data.get("angle_unit", "deg")
    if angle_unit not in ("deg", "rad"):
        raise ViewError(N_("angle_unit must be 'deg' or 'rad', got {got}"), got=repr(angle_unit)[:100])
    rows = data.get("configuration", [])
    if not isinstance(rows, list) or not all(isinstance(r, dict) for r in rows):
        raise ViewError(N_("configuration must be a list of tables ([[configuration]] with name and q)"))
    if len(rows) > MAX_STORED:
        raise ViewError(N_("at most {most} configurations, got {k}"), most=MAX_STORED, k=len(rows))
    scale = _joint_scale(robot) if angle_unit == "deg" else np.ones(robot.n)
    out = []
    for i, row in enumerate(rows):
        name, q = _checked_entry(robot, row.get("name"), row.get("q"), i + 1)
        q = q / scale
        bad = robot.limit_violations(q)
        if bad:
            raise ViewError(N_("configuration {k} ({name!r}): joint limit: {details}"), k=i + 1, name=name,
                            details="; ".join(bad))
        out.append((name, q))
    return out


def _stored_json(robot: Robot, entries: Sequence[tuple[str, Array]]) -> str:
    return json.dumps({"armkit": 1, "robot": robot.name,
                       "configurations": [{"name": n, "q": [float(v) for v in q]} for n, q in entries]})


def _read_stored_json(robot: Robot, text: str) -> list[tuple[str, Array]]:
    """The list kept in a browser (JSON, q in rad / robot unit); entries outside the limits are dropped."""
    try:
        data = json.loads(text)
    except ValueError as exc:
        raise ViewError(N_("not JSON: {why}"), why=str(exc)) from exc
    rows = data.get("configurations") if isinstance(data, dict) else None
    if not isinstance(rows, list) or not all(isinstance(r, dict) for r in rows):
        raise ViewError(N_("no list of configurations"))
    out: list[tuple[str, Array]] = []
    for i, row in enumerate(rows[:MAX_STORED]):
        name, q = _checked_entry(robot, row.get("name"), row.get("q"), i + 1)
        if robot.within_limits(q) and name not in {n for n, _ in out}:
            out.append((name, q))
    return out


# ---------------------------------------------------------------------- the panels
class _Stored:
    """One browser's stored configurations: its own widgets (``client.gui``) and its ``localStorage``."""

    def __init__(self, owner: "Readouts", client: Any) -> None:
        self.owner, self.client = owner, client
        self.view, self.robot = owner.view, owner.robot
        self.entries: list[tuple[str, Array]] = []
        self.lock = threading.Lock()
        L = owner._l
        gui = client.gui
        self.key = STORAGE_KEY.format(robot=re.sub(r"[^A-Za-z0-9_.-]", "_", self.robot.name))
        self.kept: Optional[str] = None
        note = ""
        try:
            if client.client_id not in owner.view.server.get_clients():   # closed as soon as it opened: no one to ask
                raise RuntimeError("the browser left")
            raw = client.local_storage.get_item(self.key, timeout=10.0)
            self.kept = owner.view.url
            if raw:
                self.entries = _read_stored_json(self.robot, raw)
        except ViewError as exc:
            note = L("bad_stored", why=owner.explain(exc))
        except (RuntimeError, TimeoutError) as exc:      # storage blocked, or a browser that does not answer
            note = L("not_kept", why=str(exc).splitlines()[0] if str(exc) else type(exc).__name__)
        self.folder = gui.add_folder(L("stored"), expand_by_default=False,   # right under "Frames and camera"
                                     order=float(owner.frames_folder.order) + 0.5)
        with self.folder:
            self.name_box = gui.add_text(L("name"), self._next_name())
            self.save_btn = gui.add_button(L("save"))
            self.list_dd = gui.add_dropdown(L("list"), self._names(), initial_value=self._names()[-1])
            self.recall_btn = gui.add_button(L("recall"))
            self.rename_btn = gui.add_button(L("rename"))
            self.delete_btn = gui.add_button(L("delete"))
            self.export_btn = gui.add_button(L("export"))
            self.upload = gui.add_upload_button(L("import"), mime_type="application/toml,.toml,text/plain")
            self.status = gui.add_html("")
        self.save_btn.on_click(lambda e: self._guard(self.save))
        self.recall_btn.on_click(lambda e: self._guard(self.recall))
        self.rename_btn.on_click(lambda e: self._guard(self.rename))
        self.delete_btn.on_click(lambda e: self._guard(self.delete))
        self.export_btn.on_click(lambda e: self._guard(self.export))
        self.upload.on_upload(lambda e: self._guard(self.import_file))
        self._say(note or (L("kept_where", address=self.view.url) if self.kept else ""), error=bool(note))

    # ---------------------------------------------------------------- helpers
    def _names(self) -> list[str]:
        return [n for n, _ in self.entries] or ["—"]

    def _next_name(self) -> str:
        k = len(self.entries) + 1
        names = {n for n, _ in self.entries}
        while self.owner._l("default_name", k=k) in names:
            k += 1
        return self.owner._l("default_name", k=k)

    def _say(self, text: str, error: bool = False, extra: str = "") -> None:
        colour = "#b91c1c" if error else "inherit"
        self.status.content = (f'<div class="armkit-stored-status" data-error="{int(error)}" style="color:{colour};'
                               f'font-size:0.8em;padding:0 0.5em;word-break:keep-all;overflow-wrap:anywhere">'
                               f'{html.escape(text)}</div>{extra}')

    def _guard(self, action: Any) -> None:
        with self.lock:
            try:
                action()
            except ArmkitError as exc:
                self._say(self.owner.explain(exc), error=True)

    def _chosen(self) -> Optional[int]:
        names = [n for n, _ in self.entries]
        value = str(self.list_dd.value)
        return names.index(value) if value in names else None

    def _refresh(self, chosen: Optional[str] = None) -> None:
        """The dropdown, the next default name, and the browser's copy of the list."""
        names = self._names()
        self.list_dd.options = names
        self.list_dd.value = chosen if chosen in names else names[-1]
        self.name_box.value = self._next_name()
        if self.kept is not None:
            self.client.local_storage.set_item(self.key, _stored_json(self.robot, self.entries))
        self.client.flush()

    # ---------------------------------------------------------------- actions
    def save(self) -> None:
        L = self.owner._l
        name = _clean_name(self.name_box.value) or self._next_name()
        q = self.view.q
        names = [n for n, _ in self.entries]
        if name in names:
            self.entries[names.index(name)] = (name, q)
            msg = L("replaced", name=name)
        elif len(self.entries) >= MAX_STORED:
            self._say(L("full", k=MAX_STORED), error=True)
            return
        else:
            self.entries.append((name, q))
            msg = L("saved", name=name)
        self._refresh(name)
        self._say(msg)

    def recall(self) -> None:
        i = self._chosen()
        if i is None:
            self._say(self.owner._l("nothing_chosen"), error=True)
            return
        name, q = self.entries[i]
        self.view.set_q(q)
        self._say(self.owner._l("recalled", name=name))

    def rename(self) -> None:
        L = self.owner._l
        i = self._chosen()
        if i is None:
            self._say(L("nothing_chosen"), error=True)
            return
        new = _clean_name(self.name_box.value)
        old, q = self.entries[i]
        if not new or new == old:
            return
        if new in [n for n, _ in self.entries]:
            self._say(L("name_taken", name=new), error=True)
            return
        self.entries[i] = (new, q)
        self._refresh(new)
        self._say(L("renamed", old=old, new=new))

    def delete(self) -> None:
        i = self._chosen()
        if i is None:
            self._say(self.owner._l("nothing_chosen"), error=True)
            return
        name, _ = self.entries.pop(i)
        self._refresh()
        self._say(self.owner._l("deleted", name=name))

    def toml(self) -> str:
        return configurations_toml(self.robot, self.entries)

    def export(self) -> None:
        text = self.toml()
        safe = re.sub(r"[^A-Za-z0-9_.-]", "_", self.robot.name) or "arm"
        pre = (f'<pre class="armkit-stored-toml" style="font-size:0.75em;margin:0.2em 0.5em;max-height:12em;'
               f'overflow:auto;white-space:pre">{html.escape(text)}</pre>')
        self._say(self.owner._l("exported", k=len(self.entries)), extra=pre)
        self.client.send_file_download(f"armkit-{safe}-configurations.toml", text.encode("utf-8"),
                                       save_immediately=True)

    def import_file(self) -> None:
        data = bytes(self.upload.value.content)
        if len(data) > MAX_IMPORT_BYTES:
            raise ViewError(N_("the file is larger than {mb} MB"), mb=MAX_IMPORT_BYTES // 1_000_000)
        try:
            text = data.decode("utf-8")
        except UnicodeDecodeError as exc:
            raise ViewError(N_("not a UTF-8 text file: {why}"), why=str(exc)) from exc
        new = parse_configurations_toml(self.robot, text)
        merged = dict(self.entries)
        merged.update(new)
        if len(merged) > MAX_STORED:
            self._say(self.owner._l("full", k=MAX_STORED), error=True)
            return
        self.entries = list(merged.items())
        self._refresh(new[-1][0] if new else None)
        self._say(self.owner._l("imported", k=len(new)))

    def remove(self) -> None:
        self.folder.remove()


class Readouts:
    """The teaching readouts of one view (see the module docstring).

    Parameters
    ----------
    view : View
        The handle; used through its public attributes (``robot``, ``server``, ``q``,
        ``set_q``, ``url``).
    lang : {"en", "ko"}
    decimals : int
        Decimals of a length in the robot's unit (the end-pose panel's).
    """

    def __init__(self, view: "View", lang: str, decimals: int) -> None:
        self.view, self.robot, self.lang = view, view.robot, lang
        self.server: Any = view.server
        self.dec = int(decimals)
        r = self.robot
        self.s = r.unit_scale
        self.reach_m = (r.reach or 1.0) * self.s
        self.stored: dict[int, _Stored] = {}          # client id -> its stored configurations
        self.dh_nodes: list[Any] = []                  # the DH frames' nodes while they are shown
        self._removed = False
        # the panels rebuilt (the page's language switch): the old readouts leave, their toggles stay
        old: Any = getattr(getattr(view, "panels", None), "readouts", None)
        on = {"j": False, "triad": True, "numbers": True, "dh": False}
        if isinstance(old, Readouts):
            on = old.toggles()
            old.remove()
        gui, sc, L = self.server.gui, self.server.scene, self._l
        with gui.add_folder(L("readouts")):
            self.t_caption = gui.add_markdown(html.escape(L("t_caption", unit=r.unit)))
            self.t_html = gui.add_html("")
            self.j_cb = gui.add_checkbox(L("show_j"), on["j"])
            self.j_html = gui.add_html("")
        self.frames_folder = gui.add_folder(L("frames"), expand_by_default=False)
        with self.frames_folder:
            self.triad_cb = gui.add_checkbox(L("world_triad"), on["triad"])
            self.numbers_cb = gui.add_checkbox(f'{L("frame_numbers")} {{0}} … {{{r.n}}}', on["numbers"])
            self.dh_cb = gui.add_checkbox(L("dh_frames"), on["dh"])
            self._preset_names = {L(p): p for p in CAMERA_PRESETS}
            self.camera_buttons = gui.add_button_group(L("camera"), list(self._preset_names))
        self.j_cb.on_update(lambda e: self._refresh_now())
        self.triad_cb.on_update(self._toggle_triad)
        self.numbers_cb.on_update(lambda e: self._refresh_now())
        self.dh_cb.on_update(self._toggle_dh)
        self.camera_buttons.on_click(self._camera_clicked)
        # the world triad, labelled; frame numbers at the frame origins
        axis = 0.3 * self.reach_m
        self.triad = [sc.add_frame("/readouts/world", axes_length=axis, axes_radius=0.006 * self.reach_m)]
        for k, name in enumerate("xyz"):
            tip = np.zeros(3)
            tip[k] = 1.08 * axis
            self.triad.append(sc.add_label(f"/readouts/world/{name}", name, position=tuple(tip),
                                           anchor="center-center", font_screen_scale=0.9))
        self.triad.append(sc.add_label("/readouts/world/name", L("world"), position=(0.0, 0.0, 0.0),
                                       anchor="top-right", font_screen_scale=0.8))
        self.numbers = [sc.add_label(f"/readouts/numbers/{k}", f"{{{k}}}", anchor="bottom-left",
                                     font_screen_scale=0.8) for k in range(r.n + 1)]
        self._toggle_triad(None)
        if on["dh"]:
            self._add_dh()
        self.server.on_client_connect(self._client_connected)
        self.server.on_client_disconnect(self._client_left)

    def _l(self, key: str, **fields: object) -> str:
        return translate(TEXTS[key], self.lang, **fields)

    def explain(self, exc: BaseException) -> str:
        """An error's text in the page's language: a :class:`ViewError` from its template and fields, any other
        armkit error by :func:`armkit.locale.library.localize` (its template and fields; plain English stays)."""
        if isinstance(exc, ViewError):
            return translate(exc.template, self.lang, **exc.fields)
        if isinstance(exc, ArmkitError):
            return localize(exc, self.lang)
        return str(exc)

    # ---------------------------------------------------------------- per browser
    def _client_connected(self, client: Any) -> None:
        if self._removed:
            return
        stored = _Stored(self, client)
        old = self.stored.pop(client.client_id, None)
        if old is not None:
            old.remove()
        self.stored[client.client_id] = stored

    def _client_left(self, client: Any) -> None:
        self.stored.pop(client.client_id, None)

    def _camera_clicked(self, event: Any) -> None:
        client = event.client
        preset = self._preset_names.get(str(self.camera_buttons.value))
        if client is None or preset is None:
            return
        self.set_camera(client, preset)

    def set_camera(self, client: Any, preset: str) -> None:
        """Move ``client``'s camera to ``preset`` (:func:`camera_preset`), +z up."""
        try:
            fov = float(client.camera.fov)
        except AssertionError:        # viser: no camera reported yet
            fov = math.radians(50.0)
        position, look_at = camera_preset(self.robot, preset, fov)
        with client.atomic():      # position first: viser moves look_at with it, so look_at is set after
            client.camera.up_direction = (0.0, 0.0, 1.0)
            client.camera.position = tuple(position)
            client.camera.look_at = tuple(look_at)
        client.flush()

    # ---------------------------------------------------------------- state
    def _refresh_now(self) -> None:
        """Redraw the readouts of the current ``q`` (a toggle changed), in one batch."""
        q = self.view.q
        with self.server.atomic():
            self.show_state(q, fk_frames(self.robot, q))
        self.server.flush()

    def show_state(self, q: Array, F: Array) -> None:
        """Refresh T (and J), the frame numbers and the DH frames for ``q`` (frames ``F``).

        Called by the panels inside the view's batch (``server.atomic()``).
        """
        r, L = self.robot, self._l
        self.t_html.content = matrix_html(F[-1], [4, 4, 4, self.dec], "armkit-T", L("copy"), L("copied"))
        if self.j_cb.value:
            decimals = np.array([self.dec] * 3 + [4] * 3)[:, None]      # v rows in the robot's unit, ω rows in rad
            self.j_html.content = (f'<div style="font-size:0.75em;padding:0 0.5em;word-break:keep-all">'
                                   f'{html.escape(L("j_caption", unit=r.unit))}</div>'
                                   + matrix_html(jacobian(r, q), decimals, "armkit-J", L("copy"), L("copied"),
                                                 rows=("vx", "vy", "vz", "ωx", "ωy", "ωz"), columns=r.joint_names))
        else:
            self.j_html.content = ""
        shown = bool(self.numbers_cb.value)
        if shown:
            tol = 1e-6 * self.reach_m / self.s
            groups = dict(frame_number_groups(F, tol))
            for k, node in enumerate(self.numbers):
                if k in groups:
                    node.text = groups[k]
                    node.position = tuple(F[k, :3, 3] * self.s)
                node.visible = k in groups
        else:
            for node in self.numbers:
                node.visible = False
        for node, T in zip(self.dh_nodes, F):
            node.position = tuple(T[:3, 3] * self.s)
            node.wxyz = tuple(wxyz_from_rotation(T[:3, :3]))

    def _toggle_triad(self, event: Any = None) -> None:
        for node in self.triad:
            node.visible = bool(self.triad_cb.value)

    def _toggle_dh(self, event: Any) -> None:
        """Add the DH frames' nodes (x and z arrows at each frame), or remove them."""
        for node in self.dh_nodes:
            node.remove()
        self.dh_nodes = []
        if self.dh_cb.value:
            self._add_dh()
        self._refresh_now()

    def _add_dh(self) -> None:
        """A node per frame of :func:`armkit.fk_frames` with its x (red) and z (blue) axes as arrows."""
        sc = self.server.scene
        length = 0.22 * self.reach_m
        pts = np.array([[[0.0, 0.0, 0.0], [length, 0.0, 0.0]], [[0.0, 0.0, 0.0], [0.0, 0.0, length]]])
        for k in range(self.robot.n + 1):
            node = sc.add_frame(f"/readouts/dh/{k}", show_axes=False)
            sc.add_arrows(f"/readouts/dh/{k}/xz", pts, np.array([X_COLOUR, Z_COLOUR]),
                          shaft_radius=0.006 * self.reach_m, head_radius=0.016 * self.reach_m,
                          head_length=0.035 * self.reach_m)
            self.dh_nodes.append(node)

    def toggles(self) -> dict[str, bool]:
        """Which parts are shown: ``j``, ``triad``, ``numbers``, ``dh``."""
        return {"j": bool(self.j_cb.value), "triad": bool(self.triad_cb.value),
                "numbers": bool(self.numbers_cb.value), "dh": bool(self.dh_cb.value)}

    def remove(self) -> None:
        """Take every widget and node of the readouts out of the page (before the panels are rebuilt)."""
        self._removed = True
        for st in list(self.stored.values()):
            st.remove()
        self.stored.clear()
        for node in [self.triad[0], *self.numbers, *self.dh_nodes]:   # the triad's labels go with its node
            node.remove()
        self.dh_nodes = []
