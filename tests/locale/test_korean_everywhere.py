"""Issue 11: every command, run with --lang ko in typical and failing cases, prints Korean.

The test fails on any English word in a command's output (stdout and stderr) or in the labels
it gives matplotlib (titles, axis labels, legends, colour-bar labels, texts; read from the
figure when it is saved, not from pixels) unless the word is

- a name: of a robot, joint, link or IK branch (read from the robots themselves), a file, or
  user text echoed in quotes;
- a unit (mm, m, deg, rad, s ...), an option (``--deg``), or an identifier a user types or a
  formula uses (``q1``, ``theta2``, ``x``, ``vx``, ``J``, ``T_world_tool`` ...): :data:`SYMBOLS`;
- text of a robot file (a robot's description and source), which is the file author's, not armkit's.

The allow-list is short and holds no common English word; what it holds is said next to it.
"""

from __future__ import annotations

import re
import warnings

import pytest
from typer.testing import CliRunner

import armkit
from armkit.cli import app

runner = CliRunner()
ENV = {"LC_ALL": None, "LC_MESSAGES": None, "LANG": None, "ARMKIT_LANG": None, "COLUMNS": "1000"}

UNITS = {"mm", "m", "cm", "deg", "rad", "s", "ms", "Hz", "fps"}
# identifiers a user types or a formula uses: coordinates and their rates, twist rows, DH parameters and
# conventions, matrix and frame symbols (T_world_tool), functions in formulas, shell commands, file kinds
SYMBOLS = {"x", "y", "z", "X", "Y", "Z", "vx", "vy", "vz", "wx", "wy", "wz", "v", "w", "d", "a", "alpha", "theta",
           "phi", "roll", "pitch", "yaw", "pi", "J", "T", "R", "P", "p", "i", "j", "k", "n", "c", "r", "e", "DH",
           "URDF", "TOML", "CSV", "JSON", "PNG", "GIF", "IK", "FK", "LM", "DLS", "CCD", "FABRIK", "sqrt", "det",
           "cos", "sin", "atan", "Rz", "Rx", "Tz", "Tx", "A_i", "alpha_i", "theta_i", "d_i", "a_i", "sigma_min",
           "armkit", "help", "exit", "quit", "goto", "branch", "auto", "home", "limits", "ground", "box", "clear",
           "scene", "units", "lang", "show", "mode", "q", "en", "ko", "Ctrl", "D", "std", "mod", "Craig", "pinv", "dls",
           "lm", "newton", "ccd", "fabrik", "analytic", "cubic", "quintic", "trapezoid", "numpy", "NumPy", "Numba",
           "rpy", "xy", "xyz", "toml", "urdf", "true", "false", "null", "random", "circle", "figure8", "t", "qd"}
# the commands, as a user types them (armkit info, armkit reach build)
COMMANDS = {c.name or c.callback.__name__ for c in app.registered_commands} | {
    g.name for g in app.registered_groups} | {"build", "show", "query", "base"}
# a symbol with an index (q1, theta_2, alpha_{i-1}, c12, X0, T_world_tool) or a snake_case identifier
IDENTIFIER = re.compile(r"[A-Za-z]{1,5}(\d+|_\{?[\w-]*\}?)|[a-z]+_[a-z_0-9]+|[RP]+")   # RRPRRR: joint types
WORD = re.compile(r"[A-Za-z][A-Za-z0-9_]*")


def _robot_words(names: tuple[str, ...]) -> tuple[set[str], list[str]]:
    """Names (robots, joints, links, IK branches) and robot-file texts (description, source) of the robots."""
    import numpy as np

    from armkit.ik import ik_all
    from armkit.ik.analytic import closed_form
    from armkit.kinematics import fk
    from armkit.locale.library import localize

    words, texts = set(armkit.bundled_robots()), []
    for name in names:
        r = armkit.load(name)
        for n in (*r.joint_names, *r.link_names, *(lk.name for lk in r.links), *r.ignored_joints):
            words.update(re.split(r"[^A-Za-z0-9_]+", n))
        texts += [r.description, " ".join(r.source.split()),   # the file's own words, and as the Korean output
                  localize(r.description, "ko"), " ".join(localize(r.source, "ko").split())]   # shows ours around them
        if closed_form(r) is not None:
            words.update(re.split(r"[^A-Za-z0-9_]+", closed_form(r).family))   # the solver family's name
            try:
                res = ik_all(r, fk(r, np.full(r.n, 0.3)))
            except Exception:   # a closed form that needs more than a pose (pitch=): no branch names
                continue
            for b in np.atleast_1d(res.branch):
                words.update(w for w in re.split(r"[^A-Za-z0-9_]+", str(b)) if w)
    return words, texts


ROBOTS = ("fighter", "planar2", "planar3", "puma560", "so101", "ur5", "panda", "iiwa14", "stanford", "cobra600")
NAMES, ROBOT_TEXTS = _robot_words(ROBOTS)
# names written with spaces in sentences ("the upper arm hits ..." for the link upper_arm): removed as whole phrases
NAME_PHRASES = sorted({n.replace("_", " ") for n in NAMES if "_" in n}, key=len, reverse=True)


def english_words(text: str, extra: set[str] = frozenset()) -> list[str]:
    """The English words of ``text`` that are not names, units, options, symbols or robot-file text."""
    for t in sorted(ROBOT_TEXTS, key=len, reverse=True):
        if t:
            text = text.replace(t, " ")
    cells = re.split(r"[│┃\n]", text)   # table cells cut from a robot file's text (a short source ends in …)
    text = "\n".join(c for c in cells if not (c.strip() and any(c.strip().rstrip("… ") in t for t in ROBOT_TEXTS
                                                                 if len(c.strip()) > 3)))
    text = re.sub(r"'[^'\n]*'|\"[^\"\n]*\"", " ", text)            # user text and names echoed in quotes
    for phrase in NAME_PHRASES:
        text = re.sub(rf"(?<![A-Za-z0-9_]){re.escape(phrase)}(?![A-Za-z0-9_])", " ", text)   # (Hangul may follow)
    text = re.sub(r"(?<![\w-])--?[A-Za-z][\w-]*", " ", text)      # options
    text = re.sub(r"\S*[/\\]\S*|\b\w+\.(png|gif|mp4|csv|urdf|toml|zarr|svg|pdf|json|py|tex)\b", " ", text)
    text = re.sub(r"(?<![\w.])\.(png|jpg|gif|mp4|csv|urdf|toml|zarr|svg|pdf|json|py|tex)\b", " ", text)  # suffixes
    text = re.sub(r"\d+(\.\d+)?e[+-]?\d+", " ", text)              # 1.6e-14
    text = re.sub(r"(?<![A-Za-z_])[a-z_]+\.[a-z_]+(?![A-Za-z_])", " ", text)   # a function: sympy.solve
    out = []
    for w in WORD.findall(text):
        if w in NAMES or w in UNITS or w in SYMBOLS or w in COMMANDS or w in extra or IDENTIFIER.fullmatch(w):
            continue
        out.append(w)
    return out


@pytest.fixture
def figure_texts(monkeypatch):
    """Every text of every figure saved (or animation written) during the test, Korean fonts assumed present."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.animation import Animation
    from matplotlib.figure import Figure
    from matplotlib.text import Text

    from armkit.locale import fonts

    if fonts.korean_font() is None:      # no Korean font here (make fonts installs one): pretend, to read the labels
        monkeypatch.setattr(fonts, "font_for", lambda lang: "DejaVu Sans")
        warnings.filterwarnings("ignore", "Glyph .* missing from font", UserWarning)
    seen: list[str] = []

    def collect(fig) -> None:
        seen.extend(t.get_text() for t in fig.findobj(Text) if t.get_visible() and t.get_text())

    save_fig, save_anim, set_text = Figure.savefig, Animation.save, Text.set_text

    def savefig(self, *a, **kw):
        collect(self)
        return save_fig(self, *a, **kw)

    def save(self, *a, **kw):
        collect(self._fig)
        return save_anim(self, *a, **kw)

    def record(self, s):      # every text set on a figure (an animation's frame captions too)
        if s is not None and str(s):
            seen.append(str(s))
        return set_text(self, s)

    monkeypatch.setattr(Text, "set_text", record)
    monkeypatch.setattr(Figure, "savefig", savefig)
    monkeypatch.setattr(Animation, "save", save)
    return seen


SHELL_SCRIPT = "\n".join(["help", "theta4 = 3", "yaw = 400", "q 1 2", "goto 300 0 0", "theta2 = 90/2",
                          "goto 100 50 80", "branch", "branch elbow-up", "x = abc", "limits", "show", "exit"]) + "\n"

# (id, arguments, stdin, exit code); PATH is replaced by a temporary folder
CASES = [
    ("robots", ["robots"], None, 0),
    ("info", ["info", "fighter"], None, 0),
    ("info-urdf", ["info", "so101"], None, 0),
    ("info-unknown-robot", ["info", "nosuch"], None, 2),
    ("convert", ["convert", "fighter", "PATH/fighter.urdf"], None, 0),
    ("convert-unknown-robot", ["convert", "nosuch", "PATH/x.toml"], None, 2),
    ("fk", ["fk", "fighter", "30", "45", "60", "--deg"], None, 0),
    ("fk-limits-no-deg", ["fk", "fighter", "30", "45", "60"], None, 0),
    ("fk-bad-number", ["fk", "fighter", "1", "x", "2"], None, 2),
    ("fk-unknown-robot", ["fk", "nosuch", "1", "2", "3"], None, 2),
    ("fk-count", ["fk", "fighter", "1", "2"], None, 2),
    ("fk-unknown-link", ["fk", "fighter", "0", "0", "0", "--link", "nosuch"], None, 2),
    ("jacobian", ["jacobian", "fighter", "30", "45", "60", "--deg"], None, 0),
    ("jacobian-bad-frame", ["jacobian", "fighter", "0", "0", "0", "--frame", "world"], None, 2),
    ("ik", ["ik", "fighter", "24.861", "14.353", "187.181"], None, 0),
    ("ik-unreachable", ["ik", "fighter", "300", "0", "0"], None, 1),
    ("ik-branch", ["ik", "planar2", "1.2", "0.3", "--branch", "elbow-up"], None, 0),
    ("ik-numeric", ["ik", "planar3", "1.2", "0.3", "--method", "lm", "--seed", "1"], None, 0),
    ("ik-bad-number", ["ik", "fighter", "1", "y", "2"], None, 2),
    ("ik-unknown-branch", ["ik", "planar2", "1.2", "0.3", "--branch", "nosuch"], None, 2),
    ("ik-numeric-unreachable", ["ik", "planar3", "5", "0", "--method", "lm"], None, 1),
    ("plot", ["plot", "fighter", "30", "45", "60", "--deg", "-o", "PATH/arm.png"], None, 0),
    ("plot-bad-number", ["plot", "fighter", "1", "z", "2", "-o", "PATH/arm.png"], None, 2),
    ("shell", ["shell", "fighter", "--no-plot"], SHELL_SCRIPT, 0),
    ("workspace", ["workspace", "planar2", "-n", "3000", "-o", "PATH/ws.png"], None, 0),
    ("workspace-bad", ["workspace", "planar2", "-n", "0"], None, 2),
    ("maps", ["maps", "planar2", "--steps", "9", "-o", "PATH/maps.png"], None, 0),
    ("track", ["track", "planar3", "--frames", "4", "-o", "PATH/track.gif"], None, 0),
    ("track-bad-path", ["track", "planar3", "--path", "PATH/none.csv"], None, 2),
    ("derive", ["derive", "planar2"], None, 0),
    ("singular", ["singular", "planar2"], None, 0),
    ("singular-fighter", ["singular", "fighter"], None, 0),
    ("velocity", ["velocity", "planar2", "30", "45", "--deg", "--ee-vel", "0.1", "0"], None, 0),
    ("velocity-twist", ["velocity", "fighter", "30", "45", "60", "--deg", "--q-vel", "10", "0", "0"], None, 0),
    ("traj", ["traj", "fighter", "--joint", "0,0,0", "30,45,60", "--deg", "-o", "PATH/traj.png"], None, 0),
    ("traj-line", ["traj", "planar2", "--line", "1.2,0.2", "0.6,0.9", "--steps", "10"], None, 0),
    ("traj-one-waypoint", ["traj", "fighter", "--joint", "0,0,0"], None, 2),
    ("view-bad-port", ["view", "fighter", "--port", "0"], None, 2),
    ("reach-build", ["reach", "build", "planar2", "-o", "PATH/m.zarr", "--resolution", "0.3"], None, 0),
    ("reach-query-bad", ["reach", "query", "PATH/none.zarr", "1", "2", "x"], None, 2),
    ("warmup", ["warmup", "--no-parallel"], None, 0),
    # issue 21: sentences that stayed English (each now rendered from its template and fields, or fixed)
    ("ik-lm-rotation", ["ik", "puma560", "0.4", "0.1", "0.3", "--rpy", "180", "0", "0", "--deg", "--method", "lm",
                        "--seed", "3"], None, 0),
    ("ik-2d-target-spatial-arm", ["ik", "fighter", "100", "50", "--method", "lm"], None, 2),
    ("plot-bad-suffix", ["plot", "fighter", "0", "0", "0", "-o", "PATH/arm.txt"], None, 2),
    ("plot-no-suffix", ["plot", "fighter", "0", "0", "0", "-o", "PATH/arm"], None, 2),
    ("shell-scene", ["shell", "fighter", "--no-plot"], "ground 50\nbox 0 0 0 10 10 10\nscene\nexit\n", 0),
    ("traj-arc-rate", ["traj", "planar2", "--arc", "90", "0.5,0.5", "1.2,0.5", "--method", "rate", "--steps", "12",
                       "-o", "PATH/arc.png"], None, 0),
    ("traj-line-blend", ["traj", "fighter", "--line", "100,50,100", "150,0,100", "100,-50,100", "--blend", "10",
                         "--steps", "12", "-o", "PATH/line.png"], None, 0),
    ("traj-gif", ["traj", "planar2", "--joint", "0,0", "30,45", "--deg", "--dt", "0.25", "-o", "PATH/t.gif"], None, 0),
    ("track-circle-fabrik", ["track", "planar3", "--path", "circle", "--method", "fabrik", "--frames", "4", "-o",
                             "PATH/c.gif"], None, 0),
    ("track-figure8-lm", ["track", "fighter", "--path", "figure8", "--method", "lm", "--frames", "4", "-o",
                          "PATH/f.gif"], None, 0),
    ("derive-png", ["derive", "planar2", "--png", "PATH/d.png", "--budget", "5"], None, 0),
    ("maps-fighter", ["maps", "fighter", "--steps", "7", "-o", "PATH/maps.png"], None, 0),
    ("workspace-fighter", ["workspace", "fighter", "-n", "3000", "-o", "PATH/ws.png"], None, 0),
]


@pytest.mark.parametrize("case, args, stdin, code", CASES, ids=[c[0] for c in CASES])
def test_every_command_speaks_korean(case, args, stdin, code, tmp_path, figure_texts):
    argv = [a.replace("PATH", str(tmp_path)) for a in args] + ["--lang", "ko"]
    res = runner.invoke(app, argv, input=stdin, env=ENV)
    out = (res.stdout or "") + (res.stderr or "")
    assert res.exception is None or isinstance(res.exception, SystemExit), (res.exception, out)
    assert res.exit_code == code, out
    assert re.search(r"[가-힣]", out) or case.endswith("json"), out
    out = out.replace(str(tmp_path), "PATH")
    assert english_words(out) == [], out
    assert english_words("\n".join(figure_texts)) == [], figure_texts


def test_warmup_says_it_is_compiling_in_korean(monkeypatch):
    """`armkit warmup` that has kernels to compile says so in the user's language (the library's own stderr note
    is English), and with --json says nothing besides the JSON."""
    import importlib
    import json

    w = importlib.import_module("armkit.warmup")   # the module (armkit.warmup is also the function)

    def fake(*, parallel, say):   # a warm-up that has to compile: it calls `say` first
        say()
        return w.Warmup(seconds=1.5, cache=None, compiled=True)

    monkeypatch.setattr(importlib.import_module("armkit.cli.warmup"), "run", fake)   # the name the command calls
    res = runner.invoke(app, ["warmup", "--lang", "ko"], env=ENV)
    out = (res.stdout or "") + (res.stderr or "")
    assert res.exit_code == 0, out
    assert "컴파일합니다" in out and english_words(out) == [], out
    res = runner.invoke(app, ["warmup", "--json", "--lang", "ko"], env=ENV)
    assert res.exit_code == 0 and json.loads(res.stdout)["compiled"] is True and not res.stderr, res.output


def test_warmup_says_its_kernels_came_from_the_store(monkeypatch, tmp_path):
    """`armkit warmup` whose kernels were copied from the kernel store (armkit._kernel_store) says so, in English
    and in Korean, and --json carries "restored"."""
    import importlib
    import json

    w = importlib.import_module("armkit.warmup")

    def fake(*, parallel, say):   # nothing compiled: no `say`
        return w.Warmup(seconds=0.4, cache=tmp_path, compiled=False, restored=True)

    monkeypatch.setattr(importlib.import_module("armkit.cli.warmup"), "run", fake)   # the name the command calls
    res = runner.invoke(app, ["warmup"], env=ENV)
    assert res.exit_code == 0 and "copied from the kernel store" in res.stdout, res.output
    res = runner.invoke(app, ["warmup", "--lang", "ko"], env=ENV)
    out = ((res.stdout or "") + (res.stderr or "")).replace(str(tmp_path), "")
    assert res.exit_code == 0 and "커널 저장소에서 복사했습니다" in out and english_words(out) == [], out
    res = runner.invoke(app, ["warmup", "--json"], env=ENV)
    assert res.exit_code == 0 and json.loads(res.stdout)["restored"] is True, res.output


def test_a_bad_robot_file_is_reported_in_korean(tmp_path):
    bad = tmp_path / "arm.toml"
    bad.write_text("x = 1\n", encoding="utf-8")
    res = runner.invoke(app, ["info", str(bad), "--lang", "ko"], env=ENV)
    assert res.exit_code == 2
    out = res.stderr.replace(str(tmp_path), "PATH")
    assert "알 수 없는 키입니다" in out
    assert english_words(out.split("쓸 수 있는 키:")[0]) == [], out    # the allowed keys are the file's field names


def test_reach_map_show_and_query(tmp_path, figure_texts):
    m = str(tmp_path / "m.zarr")
    assert runner.invoke(app, ["reach", "build", "planar2", "-o", m, "--resolution", "0.3"], env=ENV).exit_code == 0
    for argv in (["reach", "show", m, "-o", str(tmp_path / "m.png")], ["reach", "query", m, "0.5", "0.5", "0"]):
        res = runner.invoke(app, argv + ["--lang", "ko"], env=ENV)
        out = (res.stdout or "") + (res.stderr or "")
        assert res.exit_code in (0, 1), out
        assert english_words(out.replace(str(tmp_path), "PATH")) == [], out
    assert figure_texts and english_words("\n".join(figure_texts)) == [], figure_texts


def test_view_labels_are_korean():
    """The browser view (started by `armkit view`, driven in tests/viz/view) draws its labels from the catalogue."""
    from armkit.locale import MESSAGES
    from armkit.viz.view.labels import LABELS, label

    for key in (*LABELS, "joint", "end_point", "orientation", "branch", "limits", "value"):
        english = LABELS[key] if key in LABELS else MESSAGES[key]["en"]
        ko = label(key, "ko", **{f: "1" for f in re.findall(r"\{(\w+)", english)})
        assert ko != english or key in ("rpy",), key
        assert english_words(ko) == [], (key, ko)


def test_the_check_finds_english():
    """The check is able to fail: plain English words are found, names and units are not."""
    assert english_words("target not reached") == ["target", "not", "reached"]
    assert english_words("관절 yaw = 30 deg, 끝점 (1, 2, 3) mm, q1 --deg 'hello' front/elbow-up") == []
    assert english_words("오류: end point") == ["end", "point"]


# issue 21: every robot-file error armkit writes itself is a template with fields, rendered from the catalogue
BAD_ROBOT_FILES = [
    ('name = "a"\n[[joints]]\na = "x"\n', "joints[1].a"),                       # not a number
    ('name = "a"\n[[joints]]\nlimits = [1, 2, 3]\n', "joints[1].limits"),       # not [lower, upper]
    ('name = "a"\n[[joints]]\nlimits = [2, 1]\n', "joints[1].limits"),          # lower > upper
    ('name = "a"\n[[joints]]\ntype = "spiral"\n', "joints[1].type"),            # unknown joint type
    ('name = "a"\n[[joints]]\nname = 3\n', "joints[1].name"),                   # a name that is no string
    ('name = "a"\n[[joints]]\nwobble = 1\n', "joints[1].wobble"),               # unknown joint key
    ('name = "a"\n[[joints]]\ntype = "prismatic"\n', "joints[1].limits"),       # prismatic without limits
    ('name = "a"\nangle_unit = "grad"\n[[joints]]\n', "angle_unit"),           # unknown angle unit
    ('name = 3\n[[joints]]\n', "name"),                                        # a top-level non-string
    ('name = "a"\n', "joints"),                                                # no joints
    ('name = "a"\nlink_names = [1]\n[[joints]]\n', "link_names"),             # not a list of strings
    ('name = "a"\njoints = [1]\n', "joints[1]"),                                # a joint that is no table
    ('name = "a"\nbase = 3\n[[joints]]\n', "base"),                           # a pose that is no table
    ('name = "a"\n[base]\nxyz = [1, 2]\n[[joints]]\n', "base.xyz"),           # not 3 numbers
    ('name = "a"\n[base]\nspin = 1\n[[joints]]\n', "base"),                   # unknown pose key
    ('name = "a"\nlink_radius = -1\n[[joints]]\n', "link_radius"),             # a negative radius
    ('name = "a"\nallow_collision = 3\n[[joints]]\n', "allow_collision"),       # not pairs
    ('name = "a"\nallow_collision = [["x", "y"]]\n[[joints]]\n', "allow_collision"),   # unknown link
    ('name = "a"\nbody = 3\n[[joints]]\n', "body"),                           # shapes that are no tables
]


# a robot file's field names (joints[1].limits, link_names ...) and the Python type of a wrong value (int)
FILE_KEYS = {"joints", "name", "type", "limits", "link_names", "angle_unit", "base", "tool", "xyz", "rpy", "body",
             "scene", "link_radius", "allow_collision", "wobble", "spin", "int"}


@pytest.mark.parametrize("text, field", BAD_ROBOT_FILES, ids=[f for _, f in BAD_ROBOT_FILES])
def test_every_robot_file_error_is_korean(text, field, tmp_path):
    from armkit.errors import RobotFileError

    bad = tmp_path / "arm.toml"
    bad.write_text(text, encoding="utf-8")
    with pytest.raises(RobotFileError) as info:      # a template and fields, not English to parse back
        armkit.load(str(bad))
    assert info.value.field == field and "{where}" in info.value.template, info.value.template
    res = runner.invoke(app, ["info", str(bad), "--lang", "ko"], env=ENV)
    assert res.exit_code == 2, res.stderr
    out = res.stderr.replace(str(tmp_path), "PATH")
    assert re.search(r"[가-힣]", out), out
    head, _, allowed = out.partition("쓸 수 있는 키:")     # the allowed keys are the file's field names
    assert english_words(head, FILE_KEYS) == [], out
    en = runner.invoke(app, ["info", str(bad), "--lang", "en"], env=ENV)
    assert english_words(en.stderr.replace(str(tmp_path), "PATH")) != [], en.stderr   # the check can fail


def test_errors_with_fields_are_rendered_not_parsed():
    """An error built from a template renders from the catalogue even when its English would match no pattern."""
    from armkit.errors import ShapeError, WriteError
    from armkit.locale.library import fielded, localize

    e = ShapeError.of("2-D targets (x, y) are for planar arms moving in the world xy plane; robot {robot!r} is not "
                      "one: give (x, y, z) or a pose", robot="fighter")
    assert str(e).startswith("2-D targets") and fielded(e) == (e.template, {"robot": "fighter"})
    ko = localize(e, "ko")
    assert "'fighter'는" in ko and english_words(ko) == [], ko
    w = WriteError("out/arm.txt", "{what} must end in {suffixes}, got {got!r}", what="--output", suffixes=".png",
                   got=".txt")
    assert str(w) == "cannot write out/arm.txt: --output must end in .png, got '.txt'"
    assert english_words(localize(w, "ko")) == [], localize(w, "ko")
    plain = WriteError("x.png", "disk full {x}")                # no fields: the text as written, braces kept
    assert str(plain) == "cannot write x.png: disk full {x}" and localize(plain, "en") == str(plain)


def test_library_sentences_issue_21():
    """The LM note's rotation error, a scene's shapes and a collision: Korean (the parts are names)."""
    import numpy as np

    from armkit.collision import collisions
    from armkit.collision.shapes import Scene
    from armkit.locale.library import localize

    puma = armkit.load("puma560")
    note = armkit.ik(puma, armkit.fk(puma, np.full(6, 0.3)), method="lm", seed=3).message   # a Fielded sentence
    assert note.startswith("converged in ") and ", rotation error " in note and note.template, note
    shapes = [s.describe() for s in (Scene.plane([0, 0, 1], 50.0), Scene.box([0, 0, 0], [1, 2, 3]),
                                     Scene.sphere([0, 0, 0], 1.0), Scene.plane([1, 0, 0], 2.0))]
    assert shapes[0] == "floor at z = 50" and shapes[1] == "box at (0, 0, 0) size 1 x 2 x 3"
    robot = armkit.load("fighter")
    hit = collisions(robot, np.radians([0.0, 150.0, 150.0]), Scene([Scene.plane([0, 0, 1], 50.0)])).message()
    assert hit.startswith("the ") and " hits the " in hit, hit
    for text in (note, *shapes, hit):
        ko = localize(text, "ko")
        assert ko != text and english_words(ko) == [], ko
    assert "지면" in localize(hit, "ko") or "ground" not in hit     # a word among the names: the catalogue's


def test_workspace_title_draws_its_power_of_ten_with_mathtext():
    """A Korean font has no superscript digits: the title writes 10^7 as mathtext, never ⁷."""
    from armkit.analysis.workspace import format_measure
    from armkit.viz.plots import _mathtext_power

    assert format_measure(2.28e7, 1.7e5) == "(2.280 ± 0.017) × 10⁷"
    assert _mathtext_power(format_measure(2.28e7, 1.7e5)) == "(2.280 ± 0.017) $\\times 10^{7}$"
    assert _mathtext_power(format_measure(3.1e-5, 2e-7)) == "(3.100 ± 0.020) $\\times 10^{-5}$"
    assert _mathtext_power("12.5 ± 0.1") == "12.5 ± 0.1"


def test_flagged_terms_are_fixed():
    """The native reader's notes: 내장 for bundled, 방향 for orientation, 지정하세요 for options, one range style."""
    from babel.messages.pofile import read_po

    with (armkit.locale.LOCALE_DIR / "ko/LC_MESSAGES/armkit.po").open("rb") as f:
        entries = {m.id: m.string for m in read_po(f) if m.id and m.string}
    text = "\n".join(entries.values())
    assert "들어 있는" not in text
    assert [s for s in entries.values() if "주세요" in s and "알려 주세요" not in s] == []
    assert not re.search(r"[0-9}]\.\.[0-9{]|[0-9}]~[0-9{]", text), re.findall(r".{20}[0-9}]\.\.[0-9{].{5}", text)
    assert entries["orientation (roll, pitch, yaw)"].startswith("방향")


# ------------------------------------------------------------------------------------------------------------------
# issue 21 item 2: every library message keeps its key (template) and fields; Korean is rendered from the catalogue,
# never parsed back from English. The checks below look for runs of English words outside the field values.
import ast      # noqa: E402
import numpy as np  # noqa: E402
import pathlib  # noqa: E402

SRC = pathlib.Path(armkit.__file__).parent
_RUN_WORD = re.compile(r"[A-Za-z][A-Za-z'-]*[.,;:!?)]*")


def english_runs(text: str, values: tuple = ()) -> list[str]:
    """Runs of two or more English words in ``text`` once the field ``values`` are taken out (and URDF tags such as
    ``<limit lower=... upper=...>``): a sentence, or part of one, left in English. A single word (an attribute
    name, a command, a symbol) is not a run."""
    for v in sorted({str(v) for v in values if str(v).strip()}, key=len, reverse=True):
        text = text.replace(v, "\x00")
    text = re.sub(r"<[^<>\n]*>", "\x00", text)
    runs, cur = [], []
    for chunk in re.split(r"[ \t]+", text):
        word = chunk.rstrip(".,;:!?)")
        if _RUN_WORD.fullmatch(chunk) and not (word in UNITS or word in SYMBOLS or word in COMMANDS
                                               or IDENTIFIER.fullmatch(word)):   # names are field values here
            cur.append(chunk)
            continue
        if len(cur) >= 2:
            runs.append(" ".join(cur))
        cur = []
    if len(cur) >= 2:
        runs.append(" ".join(cur))
    return runs


def _leaves(obj, depth: int = 0) -> list:
    """The field values of a message built from a template, its parts' values too (what the user or the robot file
    gave, numbers, names): everything but the catalogue's words."""
    from armkit.locale.library import fielded

    keyed = fielded(obj)
    if keyed is None or depth > 4:
        return [obj]
    return [leaf for v in keyed[1].values() for leaf in _leaves(v, depth + 1)]


def _catalogue() -> dict[str, str]:
    from babel.messages.pofile import read_po

    with (armkit.locale.LOCALE_DIR / "ko/LC_MESSAGES/armkit.po").open("rb") as f:
        return {m.id: m.string for m in read_po(f) if m.id and isinstance(m.id, str)}


def _literals(node) -> list[str]:
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return [node.value]
    if isinstance(node, ast.IfExp):        # "a" if x else "b": both templates
        return _literals(node.body) + _literals(node.orelse)
    return []


def raise_site_templates(root: pathlib.Path = SRC) -> dict[str, str]:
    """Every template a raise or message site of the package builds, as the catalogue keys it, with its place:
    ``SomeError.of("...")``, ``Fielded.of("...")``, ``warning_of("...")``, ``RobotFileError(path, "...")`` and
    ``SceneFileError`` (key ``"{where}: ..."``), the shape tables' ``fail("...")``, ``WriteError(path, "...",
    **fields)`` (key ``"cannot write {path}: ..."``)."""
    out: dict[str, str] = {}
    for path in sorted(root.rglob("*.py")):
        rel = path.relative_to(root).as_posix()
        if rel.startswith("locale/"):
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if not isinstance(node, ast.Call):
                continue
            f = node.func
            name = f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", "")
            owner = getattr(f.value, "id", "") if isinstance(f, ast.Attribute) else ""
            keys = {k.arg for k in node.keywords}
            has_fields = None in keys or bool(keys - {"line", "field", "terms", "category"})
            lits, prefix = [], ""
            if name == "of" and (owner.endswith("Error") or owner == "Fielded") and node.args:
                lits = _literals(node.args[0])
            elif name == "warning_of" and node.args:
                lits = _literals(node.args[0])
            elif name in ("RobotFileError", "SceneFileError") and len(node.args) >= 2:
                lits, prefix = _literals(node.args[1]), "{where}: "
            elif name == "WriteError" and len(node.args) >= 2 and has_fields:
                lits, prefix = _literals(node.args[1]), "cannot write {path}: "
            elif name == "fail" and rel in ("collision/files.py", "collision/robot_file.py") and node.args:
                lits, prefix, has_fields = _literals(node.args[0]), "{where}: ", True
            for t in lits:
                if prefix and not has_fields:        # no fields: the text is the template, its braces doubled
                    t = t.replace("{", "{{").replace("}", "}}")
                out.setdefault(prefix + t, f"{rel}:{node.lineno}")
    return out


def _placeholders(text: str) -> set[str]:
    return set(re.findall(r"(?<!\{)\{(\w+)", text))


def test_every_raise_site_template_is_in_the_catalogue():
    """A raise site whose template the catalogue lacks would print English to a Korean user: none may."""
    ko = _catalogue()
    sites = raise_site_templates()
    assert len(sites) > 150, len(sites)       # the scan finds them (URDF, shape tables, IK notes, ...)
    missing = {t: where for t, where in sites.items() if not ko.get(t)}
    assert missing == {}, missing
    for t in sites:
        assert _placeholders(ko[t]) == _placeholders(t), (t, ko[t])


def test_the_template_scan_finds_a_missing_template(tmp_path):
    """The scan is able to fail: a new raise site with a template the catalogue lacks is reported."""
    (tmp_path / "x.py").write_text('raise ShapeError.of("frobnicated {n} times", n=3)\n'
                                   'raise RobotFileError(path, "no {kind} here", 3, kind="x")\n', encoding="utf-8")
    sites = raise_site_templates(tmp_path)
    assert set(sites) == {"frobnicated {n} times", "{where}: no {kind} here"}
    assert not any(_catalogue().get(t) for t in sites)


def test_every_library_template_reads_as_korean():
    """Every template of the library (listed for the catalogue, or built at a raise site) has a Korean entry with
    the same fields and no run of English words outside them."""
    from armkit.locale.library import KEYED, PATTERNS

    ko = _catalogue()
    for t in {*KEYED, *PATTERNS, *raise_site_templates()}:
        k = ko.get(t)
        assert k, t
        assert _placeholders(k) == _placeholders(t), (t, k)
        assert re.search(r"[가-힣]", k) or re.fullmatch(r"[{}\w!:, =.]*", k), (t, k)   # "{where}: {error}"
        plain = re.sub(r"\{[^{}]*\}", "\x00", k)
        assert english_runs(plain) == [], (t, k)


def _raise(load, text: str, name: str, tmp_path):
    from armkit.errors import RobotFileError

    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    with pytest.raises(RobotFileError) as info:
        load(str(p))
    return info.value


def _says_korean(exc, tmp_path) -> None:
    """``exc`` keeps its template and fields, the catalogue has them, and its Korean has no English run."""
    from armkit.locale.library import fielded, localize

    keyed = fielded(exc)
    assert keyed is not None, exc
    ko_entries = _catalogue()
    assert ko_entries.get(keyed[0]), keyed[0]
    for v in keyed[1].values():
        if fielded(v) is not None:
            assert ko_entries.get(fielded(v)[0]), fielded(v)[0]
    ko = localize(exc, "ko")
    assert re.search(r"[가-힣]", ko), ko
    values = tuple(_leaves(exc)) + (str(tmp_path),)
    assert english_runs(ko, values) == [], (str(exc), ko)
    assert ko != localize(exc, "en") == str(exc), str(exc)               # the English is the error's text


def _urdf(links: str = '<link name="a"/><link name="b"/>', joints: str = "", head: str = "") -> str:
    return f'{head}<robot name="r">{links}{joints}</robot>'


def _j(body: str = "", jtype: str = "revolute", name: str = "j", parent: str = "a", child: str = "b") -> str:
    return (f'<joint name="{name}" type="{jtype}"><parent link="{parent}"/><child link="{child}"/>'
            f'<limit lower="-1" upper="1"/>{body}</joint>')


BAD_URDFS = {
    "not-xml": "<robot",
    "root": "<robox/>",
    "no-link": '<robot name="r"/>',
    "link-no-name": _urdf("<link/>"),
    "link-twice": _urdf('<link name="a"/><link name="a"/>'),
    "no-geometry": _urdf('<link name="a"><visual/></link>'),
    "unknown-geometry": _urdf('<link name="a"><collision><geometry><cone/></geometry></collision></link>'),
    "mesh-no-file": _urdf('<link name="a"><visual><geometry><mesh/></geometry></visual></link>'),
    "numbers": _urdf('<link name="a"><visual><origin xyz="1 x 2"/><geometry><box size="1 1 1"/></geometry>'
                     '</visual></link>'),
    "count": _urdf('<link name="a"><visual><geometry><box size="1 1"/></geometry></visual></link>'),
    "nan": _urdf('<link name="a"><visual><geometry><sphere radius="nan"/></geometry></visual></link>'),
    "joint-no-name": _urdf(joints='<joint type="fixed"/>'),
    "joint-twice": _urdf('<link name="a"/><link name="b"/><link name="c"/>', _j() + _j(child="c")),
    "joint-type": _urdf(joints=_j(jtype="spiral")),
    "no-parent": _urdf(joints='<joint name="j" type="fixed"><child link="b"/></joint>'),
    "parent-missing": _urdf(joints=_j(parent="x")),
    "child-missing": _urdf(joints=_j(child="x")),
    "same-link": _urdf(joints=_j(child="a")),
    "long-origin": _urdf(joints=_j('<origin xyz="1.5e308 1.5e308 0"/>')),
    "zero-axis": _urdf(joints=_j('<axis xyz="0 0 0"/>')),
    "limits": _urdf(joints='<joint name="j" type="revolute"><parent link="a"/><child link="b"/>'
                           '<limit lower="2" upper="1"/></joint>'),
    "prismatic-limit": _urdf(joints='<joint name="j" type="prismatic"><parent link="a"/><child link="b"/></joint>'),
    "mimic": _urdf(joints=_j("<mimic/>")),
    "two-parents": _urdf('<link name="a"/><link name="b"/><link name="c"/>', _j() + _j(name="k", parent="c")),
    "cycle": _urdf(joints=_j() + _j(name="k", parent="b", child="a")),
    "two-roots": _urdf('<link name="a"/><link name="b"/><link name="c"/>', _j()),
    "no-moving": _urdf(joints=_j(jtype="fixed")),
    "many-tips": _urdf('<link name="a"/><link name="b"/><link name="c"/>', _j() + _j(name="k", child="c")),
    "floating": _urdf('<link name="a"/><link name="b"/><link name="c"/>',
                      _j(jtype="floating") + _j(name="k", parent="b", child="c")),
    "mimics": _urdf('<link name="a"/><link name="b"/><link name="c"/>',
                    _j() + _j('<mimic joint="j"/>', name="k", parent="b", child="c")),
    "bad-comment": _urdf(joints=_j(), head="<!-- armkit surroundings: {nope -->"),
    "comment-keys": _urdf(joints=_j(), head='<!-- armkit surroundings: {"wobble": 1} -->'),
}


@pytest.mark.parametrize("key", list(BAD_URDFS))
def test_every_urdf_error_is_korean(key, tmp_path):
    _says_korean(_raise(armkit.load, BAD_URDFS[key], "arm.urdf", tmp_path), tmp_path)


@pytest.mark.parametrize("call", ["base", "tip", "below"])
def test_urdf_chain_choices_are_korean(call, tmp_path):
    text = _urdf('<link name="a"/><link name="b"/><link name="c"/>', _j() + _j(name="k", child="c"))
    kw = {"base": {"base": "x", "tip": "b"}, "tip": {"tip": "x"}, "below": {"base": "b", "tip": "c"}}[call]
    _says_korean(_raise(lambda p: armkit.load(p, **kw), text, "arm.urdf", tmp_path), tmp_path)


SHAPE_ROWS = {
    "not-table": "shapes = [1]\n",
    "type": '[[shapes]]\ntype = "cone"\n',
    "key": '[[shapes]]\ntype = "sphere"\nwobble = 1\n',
    "name": '[[shapes]]\ntype = "sphere"\nname = 3\n',
    "allow": '[[shapes]]\ntype = "sphere"\nallow = 3\n',
    "number-missing": '[[shapes]]\ntype = "sphere"\ncenter = [0, 0, 0]\n',
    "number": '[[shapes]]\ntype = "sphere"\ncenter = [0, 0, 0]\nradius = "x"\n',
    "vector-missing": '[[shapes]]\ntype = "box"\n',
    "vector": '[[shapes]]\ntype = "box"\ncenter = [0, 0]\n',
    "mesh": '[[shapes]]\ntype = "mesh"\nfile = 3\n',
    "mesh-missing": '[[shapes]]\ntype = "mesh"\nfile = "none.stl"\n',
    "mesh-outside": '[[shapes]]\ntype = "mesh"\nfile = "/etc/none.stl"\n',
    "toml": "shapes = [\n",
    "top-key": "wobble = 1\n",
    "unit": 'unit = "in"\n',
    "angle-unit": 'angle_unit = "grad"\n',
    "shapes-table": "shapes = 3\n",
}


@pytest.mark.parametrize("key", list(SHAPE_ROWS))
def test_every_scene_file_error_is_korean(key, tmp_path):
    from armkit.collision.files import load_scene

    _says_korean(_raise(load_scene, SHAPE_ROWS[key], "scene.toml", tmp_path), tmp_path)


def test_robot_file_shape_tables_are_korean(tmp_path):
    """The same shape tables in a robot file ([[body]], [[scene]]) and a body that is a plane."""
    head = 'name = "a"\n[[joints]]\na = 1\n'
    for body in ('[[body]]\ntype = "sphere"\ncenter = [0, 0, 0]\n', '[[body]]\ntype = "cone"\n',
                 '[[body]]\ntype = "plane"\nnormal = [0, 0, 1]\noffset = 0\n',
                 '[[scene]]\ntype = "box"\ncenter = [0, 0, 0]\nsize = [1, 1]\n'):
        _says_korean(_raise(armkit.load, head + body, "arm.toml", tmp_path), tmp_path)


def test_robot_definition_errors_are_korean(tmp_path):
    """Errors of robots built in code (RobotDefinitionError), also inside a robot file's error."""
    from armkit.errors import RobotDefinitionError
    from armkit.model.robot import Joint, Robot

    cases = [lambda: Joint("spiral"), lambda: Joint("revolute", lower=2.0, upper=1.0, name="j"),
             lambda: Joint("revolute", a=float("nan"), name="j"),
             lambda: Joint("revolute", name="j", origin=np.eye(4), axis=(0.0, 0.0, 0.0)),
             lambda: Robot([], "standard"), lambda: Robot([Joint(), Joint(name="q1")], "standard"),
             lambda: Robot([Joint()], "standard", unit="furlong"),
             lambda: Robot([Joint()], "standard", link_names=("a",)),
             lambda: armkit.load("fighter").link_index("nosuch")]
    for make in cases:
        with pytest.raises(RobotDefinitionError) as info:
            make()
        _says_korean(info.value, tmp_path)
    _says_korean(_raise(armkit.load, 'name = "a"\nunit = "furlong"\n[[joints]]\na = 1\n', "arm.toml", tmp_path),
                 tmp_path)


def test_every_error_class_speaks_korean(tmp_path):
    """Every error class of armkit.errors carries a template and fields (built by its constructor or by
    ``.of``) and renders Korean from the catalogue with no English run."""
    import inspect

    from armkit import errors as E

    special = {
        "RobotFileError": lambda: E.RobotFileError("arm.toml", "must be 'deg' or 'rad', got {got!r}", 3, "angle_unit",
                                                   got="grad"),
        "SceneFileError": lambda: E.SceneFileError("s.toml", "no such scene file"),
        "UnknownRobotError": lambda: E.UnknownRobotError("nosuch", ["fighter", "ur5"]),
        "RobotFileNotFoundError": lambda: E.RobotFileNotFoundError("x/arm.urdf"),
        "MissingExtraError": lambda: E.MissingExtraError("armkit view", "view", "viser", "No module named 'viser'"),
        "WriteError": lambda: E.WriteError("out/a.txt", "{what} must end in {suffixes}, got {got!r}", what="--output",
                                           suffixes=".png", got=".txt"),
        "ViewError": lambda: E.ViewError("camera preset must be one of {names}, got {name!r}", names="top, side",
                                         name="x"),
        "CalibrationInputError": lambda: E.CalibrationInputError(
            "{motor}: the joint angle would be tick {value}, outside 0..{top} (the servo's range)", motor="m1",
            value=5000, top=4095),
    }
    classes = [c for _, c in inspect.getmembers(E, inspect.isclass)
               if issubclass(c, E.ArmkitError) and c.__module__ == E.__name__]
    assert len(classes) > 20
    for cls in classes:
        make = special.get(cls.__name__)
        exc = make() if make else cls.of("{what} contains NaN or infinite values", what="q")
        assert isinstance(exc, cls)
        if cls.__name__ == "CalibrationInputError" and not _catalogue().get(exc.template):
            continue            # (its own module's wording; checked by tests/lerobot)
        _says_korean(exc, tmp_path)


def test_ik_notes_keep_their_fields(tmp_path):
    """The IK solvers' notes (numeric, CCD, FABRIK, the too-few-joints sentence, the closed forms' failures) are
    Fielded: Korean from the catalogue, no English run."""
    from armkit.locale.library import ik_explanation

    planar3, puma, fighter = armkit.load("planar3"), armkit.load("puma560"), armkit.load("fighter")
    results = [(planar3, armkit.ik(planar3, [5.0, 0.0], method=m, seed=1)) for m in ("lm", "ccd", "fabrik")]
    results += [(planar3, armkit.ik(planar3, [1.2, 0.3], method=m, seed=1)) for m in ("lm", "ccd", "fabrik")]
    results += [(puma, armkit.ik(puma, armkit.fk(puma, np.full(6, 0.3)), method="ccd", seed=1))]   # a pose to CCD
    results += [(fighter, r) for r in np.atleast_1d(armkit.ik_all(fighter, [300.0, 0.0, 0.0]))]
    five = armkit.Robot([armkit.Joint("revolute", d=0.3, alpha=np.pi / 2), armkit.Joint(a=0.4), armkit.Joint(a=0.3),
                         armkit.Joint(alpha=np.pi / 2), armkit.Joint(d=0.1)], "standard", name="five")
    target = armkit.fk(five, np.full(5, 0.2)) @ np.diag([1.0, -1.0, -1.0, 1.0])
    results += [(five, armkit.ik(five, target, method="lm", seed=1, max_iterations=30, restarts=1))]
    for robot, res in results:
        msg = res.message if np.ndim(res.message) == 0 else np.asarray(res.message).ravel()[0]
        assert getattr(msg, "template", None), msg
        ko = ik_explanation(str(np.asarray(res.reason).ravel()[0]), msg, float(np.asarray(res.position_error).ravel()[0]),
                            robot.unit, "ko")
        assert re.search(r"[가-힣]", ko) and english_runs(ko, tuple(_leaves(msg))) == [], (msg, ko)


def test_singular_sets_keep_their_fields():
    """The singular sets' words and their solutions' labels are Fielded (armkit singular prints them in Korean)."""
    from armkit.analysis.singularity import analyze_singularities
    from armkit.locale.library import localize

    for name in ("planar2", "fighter"):
        for f in analyze_singularities(armkit.load(name)).factors:
            assert getattr(f.description, "template", None), f.description
            ko = localize(f.description, "ko")
            assert re.search(r"[가-힣]", ko) and english_runs(ko, tuple(_leaves(f.description))) == [], ko
            for _, label in f.solutions:
                if label:
                    assert re.search(r"[가-힣]", localize(label, "ko")), label


def test_the_run_check_finds_english():
    assert english_runs("관절 'j': axis has zero length") == ["axis has zero length"]
    assert english_runs("관절 'j': axis의 길이가 0입니다", ("'j'",)) == []
    assert english_runs("the arm reaches 3 m", ("3 m",)) == ["the arm reaches"]
