"""Issue 23, item 2: the teaching readouts of the browser view (headless chromium via Playwright, no mocks).

T and J with their copy buttons, stored configurations (save, recall, rename, export and
import as TOML, kept in the browser's localStorage), the world triad, frame numbers and DH
frames, the camera presets and the reach cloud's colour bar. References are independent of
the code under test: the club report's end point of the fighter, J by finite differences of
``fk``, viridis' published end colours, camera directions written out by hand, TOML read back
with ``tomllib``. Screenshots go to a temporary folder (docs/img under
ARMKIT_UPDATE_PICTURES=1, `make pictures`).
"""

from __future__ import annotations

import math
import re
import time
import tomllib
from pathlib import Path

import numpy as np
import pytest

import armkit
from armkit.analysis.workspace import shoulder_point, workspace
from armkit.errors import ViewError
from armkit.viz.view import View
from armkit.viz.view.drawing import rotation_from_wxyz
from armkit.viz.view.readouts import (
    MAX_STORED, STORAGE_KEY, camera_preset, configurations_toml, frame_number_groups, matrix_text, parse_configurations_toml)

from _browser import open_folder, open_page, row, tick, type_joint, wait_until
from _browser import pixels as _pixels

pytestmark = pytest.mark.browser


def _matrix(page, css: str) -> np.ndarray:
    """The numbers of a matrix readout as the page shows them (not its row and column labels)."""
    rows = page.locator(f"table.{css} tr")
    out = []
    for i in range(rows.count()):
        cells = rows.nth(i).locator("td.armkit-num")
        vals = [cells.nth(j).inner_text().strip() for j in range(cells.count())]
        if vals:
            out.append([float(v) for v in vals])
    return np.array(out)


# ---------------------------------------------------------------------- without a browser
def test_matrix_text_rows_read_back() -> None:
    M = np.array([[1.0, -0.00001, 123.456789], [-2.5, 0.5, -0.0004]])
    text = matrix_text(M, [4, 4, 3])
    assert text.splitlines() == [" 1.0000  0.0000  123.457", "-2.5000  0.5000    0.000"]   # no "-0.0000"
    back = np.array([[float(x) for x in line.split()] for line in text.splitlines()])
    assert np.all(np.abs(back - M) <= np.array([0.5e-4, 0.5e-4, 0.5e-3]) + 1e-12)
    rows = matrix_text(np.ones((2, 2)), np.array([[1], [3]]))   # decimals per row
    assert rows.splitlines() == ["  1.0    1.0", "1.000  1.000"]


def test_configurations_toml_round_trip_and_errors() -> None:
    arm = armkit.load("fighter")
    q1, q2 = np.radians([30.0, 45.0, 60.0]), np.radians([-10.0, 20.5, 0.0])
    text = configurations_toml(arm, [("reach up", q1), ('a "quoted" name', q2)])
    data = tomllib.loads(text)                         # the standard library reads it, not our parser
    assert data["robot"] == "fighter" and data["unit"] == "mm" and data["angle_unit"] == "deg"
    assert data["joints"] == ["yaw", "shoulder", "elbow"]
    assert [c["name"] for c in data["configuration"]] == ["reach up", 'a "quoted" name']
    assert data["configuration"][0]["q"] == [30.0, 45.0, 60.0]      # 12 significant digits: 30.0, not 29.999...
    assert data["configuration"][1]["q"] == [-10.0, 20.5, 0.0]
    back = parse_configurations_toml(arm, text)
    assert [n for n, _ in back] == ["reach up", 'a "quoted" name']
    assert np.allclose(back[0][1], q1, atol=1e-12) and np.allclose(back[1][1], q2, atol=1e-12)
    rad = 'angle_unit = "rad"\n[[configuration]]\nname = "r"\nq = [0.5, 0.25, 0.0]\n'
    assert np.array_equal(parse_configurations_toml(arm, rad)[0][1], [0.5, 0.25, 0.0])
    with pytest.raises(ViewError, match="not a TOML file"):
        parse_configurations_toml(arm, "q = [1, 2")
    with pytest.raises(ViewError, match="are not the joints of robot 'fighter'"):
        parse_configurations_toml(arm, 'joints = ["a", "b", "c"]\n')
    with pytest.raises(ViewError, match="unit must be 'mm'"):
        parse_configurations_toml(arm, 'unit = "m"\n')
    with pytest.raises(ViewError, match="configuration 1: q must be a list of 3 numbers"):
        parse_configurations_toml(arm, '[[configuration]]\nname = "x"\nq = [1, 2]\n')
    with pytest.raises(ViewError, match=r"configuration 1 \('far'\): joint limit"):
        parse_configurations_toml(arm, '[[configuration]]\nname = "far"\nq = [0, 0, 1000]\n')
    with pytest.raises(ViewError, match=f"at most {MAX_STORED}"):
        parse_configurations_toml(arm, '[[configuration]]\nname = "x"\nq = [0, 0, 0]\n' * (MAX_STORED + 1))


def test_camera_presets_by_hand() -> None:
    arm = armkit.load("fighter")
    s = arm.unit_scale
    centre = np.asarray(shoulder_point(arm)) * s
    expected = {"front": (1, 0, 0), "side": (0, -1, 0), "top": (0, -1e-3, 1), "iso": (1, -1, 1)}
    fov = math.radians(60.0)
    for name, d in expected.items():
        pos, look = camera_preset(arm, name, fov)
        assert np.allclose(look, centre)
        off = pos - look
        assert np.allclose(off / np.linalg.norm(off), np.array(d) / np.linalg.norm(d), atol=1e-12)
        # the reach sphere (radius R around the shoulder) fits the vertical field of view, with 10 % margin
        assert math.isclose(np.linalg.norm(off) * math.sin(fov / 2), 1.1 * arm.reach * s, rel_tol=1e-12)
    with pytest.raises(ViewError, match="camera preset must be one of front, side, top, iso"):
        camera_preset(arm, "back")


def test_frame_numbers_share_a_label_where_frames_meet() -> None:
    # the Puma 560 at zero: frames 4, 5 and 6 (the wrist) meet at one point unless its tool moves frame 6
    arm = armkit.load("puma560")
    F = armkit.fk_frames(arm, np.zeros(6))
    groups = dict(frame_number_groups(F, 1e-9))
    assert sorted(int(t.strip("{}")) for text in groups.values() for t in text.split()) == list(range(7))
    origins = F[:, :3, 3]
    for first, text in groups.items():
        members = [int(t.strip("{}")) for t in text.split()]
        assert members[0] == first
        assert all(np.linalg.norm(origins[k] - origins[first]) <= 1e-9 for k in members)
    firsts = list(groups)
    assert all(np.linalg.norm(origins[a] - origins[b]) > 1e-9 for a in firsts for b in firsts if a < b)
    assert "{4} {5}" in " | ".join(groups.values())          # the wrist centre: d5 = a5 = a4 = 0


# ---------------------------------------------------------------------- T and J in the page
def test_t_and_j_readouts_and_copy(browser, docs_img: Path) -> None:
    with View("fighter", lang="en") as v:
        page = open_page(browser, v.url, "yaw (°)")
        browser.grant_permissions(["clipboard-read", "clipboard-write"], origin=v.url.rstrip("/"))
        for j, (name, value) in enumerate((("yaw (°)", 30), ("shoulder (°)", 45), ("elbow (°)", 60))):
            type_joint(page, v, j, name, value)
        wait_until(lambda: np.allclose(v.q, np.radians([30, 45, 60]), atol=1e-12), what="q = (30, 45, 60)°")
        T = armkit.fk(v.robot, v.q)
        wait_until(lambda: _matrix(page, "armkit-T").shape == (4, 4)
                   and np.allclose(_matrix(page, "armkit-T")[:3, 3], [24.861, 14.353, 187.181], atol=0), 20,
                   "the T readout of (30, 45, 60)°")
        shown = _matrix(page, "armkit-T")
        # the club report's end point, to the printed precision, and every entry of fk to its printed decimals
        assert list(shown[:3, 3]) == [24.861, 14.353, 187.181]
        tol = np.array([0.5e-4, 0.5e-4, 0.5e-4, 0.5e-3]) + 1e-12
        assert np.all(np.abs(shown - T) <= tol), shown - T
        assert list(shown[3]) == [0.0, 0.0, 0.0, 1.0]
        # the copy button: what it carries and what lands on the clipboard are the plain rows
        btn = page.locator("button.armkit-T-copy").first
        carried = btn.get_attribute("data-copy")
        assert carried == matrix_text(T, [4, 4, 4, 3])
        btn.click()
        wait_until(lambda: page.locator("button.armkit-T-copy").first.get_attribute("data-copied") == "1"
                   or page.evaluate("navigator.clipboard.readText()") == carried, what="copied")
        clip = page.evaluate("navigator.clipboard.readText()")
        assert clip == carried
        assert np.array_equal(np.array([[float(x) for x in line.split()] for line in clip.splitlines()]), shown)
        # J on demand: the columns are fk's derivatives (central differences), written out here
        assert page.locator("table.armkit-J").count() == 0
        page.get_by_text("show J", exact=True).click()
        wait_until(lambda: page.locator("table.armkit-J").count() == 1, what="the J readout")
        J = _matrix(page, "armkit-J")
        assert J.shape == (6, 3)
        h = 1e-6
        for k in range(3):
            dq = np.zeros(3)
            dq[k] = h
            Tp, Tm = armkit.fk(v.robot, v.q + dq), armkit.fk(v.robot, v.q - dq)
            v_col = (Tp[:3, 3] - Tm[:3, 3]) / (2 * h)
            W = (Tp[:3, :3] - Tm[:3, :3]) / (2 * h) @ T[:3, :3].T      # skew(ω)
            w_col = np.array([W[2, 1], W[0, 2], W[1, 0]])
            assert np.all(np.abs(J[:3, k] - v_col) <= 0.5e-3 + 1e-5), (k, J[:3, k], v_col)
            assert np.all(np.abs(J[3:, k] - w_col) <= 0.5e-4 + 1e-7), (k, J[3:, k], w_col)
        assert page.get_by_text("J in the world frame, rows (v, ω): v in mm, ω in rad", exact=False).count() == 1
        jcopy = page.locator("button.armkit-J-copy").first.get_attribute("data-copy")
        assert np.array_equal(np.array([[float(x) for x in line.split()] for line in jcopy.splitlines()]), J)
        page.locator("table.armkit-T").first.scroll_into_view_if_needed()
        page.screenshot(path=str(docs_img / "view-readouts.png"))
        # a slider move: T follows at once (the readout is part of the same update)
        v.set_q(np.zeros(3))
        T0 = armkit.fk(v.robot, np.zeros(3))
        wait_until(lambda: np.all(np.abs(_matrix(page, "armkit-T") - T0) <= tol), what="T at q = 0")
        page.get_by_text("show J", exact=True).click()
        wait_until(lambda: page.locator("table.armkit-J").count() == 0, what="J hidden")
        page.close()


# ---------------------------------------------------------------------- stored configurations
def _stored(v: View) -> list[str]:
    clients = v.panels.readouts.stored
    return [[n for n, _ in st.entries] for st in clients.values()][-1] if clients else []


def _typed(v: View) -> str:
    """The name box as the server has it (the browser sends a typed value a moment after the keys: a button clicked
    at once can reach the server first, which a person's hand never does)."""
    clients = v.panels.readouts.stored
    return str([st.name_box.value for st in clients.values()][-1]) if clients else ""


def _type_name(box, v: View, text: str, what: str) -> None:
    """Type ``text`` in the name box and press Enter until the server has it. The server sets the box itself after
    a save, recall or rename (the next default name); on a busy machine that update can arrive after the keys and
    overwrite them, and a person would then type the name again."""
    for _ in range(6):
        box.fill(text)
        box.press("Enter")
        try:
            wait_until(lambda: _typed(v) == text, timeout=10.0, what=what)
            return
        except AssertionError:
            continue
    assert _typed(v) == text, f"timed out waiting for {what}"


def _choose(page, label: str, option: str) -> None:
    """Pick ``option`` in the drop-down list labelled ``label``, as a person would: open the list, click the option,
    and look again until the box shows it.

    Each step can be undone under the test on a busy machine, and is then done again: after a page reload the first
    click on the box can land while it is still being set up (the list stays shut); the list's opening animation can
    leave a neighbour over the option for a moment; and the server's copy of the options, arriving a moment after a
    reload, draws the list anew and shuts it (the option hidden just before the click)."""
    from playwright.sync_api import Error as PlaywrightError
    from playwright.sync_api import TimeoutError as PlaywrightTimeout

    box = row(page, label).locator("input").first
    choice = page.locator("[role=option]", has_text=option).first
    for _ in range(10):      # always one click at least: the box can show the option before the server has it
        try:
            if not choice.is_visible():
                box.click()
                choice.wait_for(state="visible", timeout=5_000)
            time.sleep(0.3)                                  # the opening animation settles
            choice.click(force=True, timeout=5_000)
        except (PlaywrightTimeout, PlaywrightError):         # shut again before the click: open it again
            continue
        try:
            wait_until(lambda: box.input_value() == option, timeout=5.0, what=f"{option!r} chosen")
            return
        except AssertionError:
            continue
    assert box.input_value() == option, f"{option!r} could not be chosen in the list {label!r}"


def _status(page) -> str:
    return str(page.locator(".armkit-stored-status").first.inner_text())


def test_stored_configurations_save_recall_rename_export_import(browser, tmp_path: Path) -> None:
    with View("fighter", lang="en") as v:
        page = open_page(browser, v.url, "yaw (°)")
        open_folder(page, "Stored configurations")
        wait_until(lambda: "kept in this browser for" in _status(page), what="the list's home said")
        q1, q2 = np.radians([30.0, 45.0, 60.0]), np.radians([-20.0, 10.0, 35.0])
        v.set_q(q1)
        page.get_by_role("button", name="Save current").click()
        wait_until(lambda: _status(page) == "saved 'pose 1'", what="saved pose 1")
        v.set_q(q2)
        box = row(page, "name").locator("input").first
        wait_until(lambda: box.input_value() == "pose 2", what="the next default name")
        _type_name(box, v, "reach", "the name typed")
        page.get_by_role("button", name="Save current").click()
        wait_until(lambda: _stored(v) == ["pose 1", "reach"], what="two stored")
        # recall: the arm goes back to what was saved, bit for bit
        _choose(page, "stored", "pose 1")
        page.get_by_role("button", name="Recall").click()
        wait_until(lambda: np.array_equal(v.q, q1), what="q back to pose 1")
        wait_until(lambda: _status(page) == "recalled 'pose 1'", what="recalled said")
        # rename, and a taken name is refused
        _type_name(box, v, "start", "the new name typed")
        page.get_by_role("button", name="Rename").click()
        wait_until(lambda: _stored(v) == ["start", "reach"], what="renamed")
        _type_name(box, v, "reach", "the taken name typed")
        page.get_by_role("button", name="Rename").click()
        wait_until(lambda: "exists; choose another name" in _status(page), timeout=60.0, what="name taken")
        assert _stored(v) == ["start", "reach"]
        # export: a TOML download that the standard library reads back to the saved q
        with page.expect_download(timeout=30_000) as dl:
            page.get_by_role("button", name="Export TOML").click()
        assert dl.value.suggested_filename == "armkit-fighter-configurations.toml"
        text = Path(dl.value.path()).read_text(encoding="utf-8")
        data = tomllib.loads(text)
        assert [c["name"] for c in data["configuration"]] == ["start", "reach"]
        got = np.radians([c["q"] for c in data["configuration"]])   # revolute joints in degrees
        assert np.allclose(got, [q1, q2], atol=1e-12)
        wait_until(lambda: page.locator("pre.armkit-stored-toml").count() == 1, what="the TOML text shown")
        assert page.locator("pre.armkit-stored-toml").first.inner_text().strip() == text.strip()
        # kept in the browser: a reload brings the list back (localStorage, not the server's memory)
        stored = page.evaluate("JSON.stringify(Object.keys(localStorage))")
        assert "armkit-configurations-fighter" in stored
        page.reload()
        page.get_by_text("yaw (°)", exact=True).first.wait_for(timeout=30_000)
        wait_until(lambda: len(v.server.get_clients()) == 1 and _stored(v) == ["start", "reach"], 20,
                   "the list back after a reload")
        open_folder(page, "Stored configurations")
        _choose(page, "stored", "reach")
        page.get_by_role("button", name="Recall").click()
        wait_until(lambda: np.array_equal(v.q, q2), what="q back to reach")
        # import: a file written by hand (degrees), then a file of another arm is refused with the reason
        good = tmp_path / "class.toml"
        good.write_text('robot = "fighter"\nunit = "mm"\nangle_unit = "deg"\n'
                        '[[configuration]]\nname = "up"\nq = [0.0, 90.0, 0.0]\n', encoding="utf-8")
        page.locator("input[type=file]").last.set_input_files(str(good))
        wait_until(lambda: _status(page) == "imported 1 configurations", what="imported")
        assert _stored(v) == ["start", "reach", "up"]
        _choose(page, "stored", "up")
        page.get_by_role("button", name="Recall").click()
        wait_until(lambda: np.allclose(v.q, np.radians([0.0, 90.0, 0.0]), atol=1e-12), what="q at up")
        bad = tmp_path / "other.toml"
        bad.write_text('joints = ["a", "b"]\n', encoding="utf-8")
        page.locator("input[type=file]").last.set_input_files(str(bad))
        wait_until(lambda: "are not the joints of robot 'fighter'" in _status(page), what="refused")
        assert page.locator(".armkit-stored-status").first.get_attribute("data-error") == "1"
        assert _stored(v) == ["start", "reach", "up"]
        # delete
        _choose(page, "stored", "start")
        page.get_by_role("button", name="Delete").click()
        wait_until(lambda: _stored(v) == ["reach", "up"], what="deleted")
        page.close()


def test_stored_list_left_out_when_the_browser_copy_is_bad(browser) -> None:
    """A list in localStorage that is not ours (or is broken) is left out with a message, never evaluated."""
    with View("fighter", lang="en") as v:
        # the bad list is in the browser's storage before the page's own scripts run (viser keeps a page's
        # values under "viser-user:" + their key): one page load, not a load and a reload
        key = "viser-user:" + STORAGE_KEY.format(robot="fighter")
        page = browser.new_page()
        page.add_init_script(f"localStorage.setItem({key!r}, '{{\"configurations\": 5}}')")
        page.goto(v.url)
        page.get_by_text("yaw (°)", exact=True).first.wait_for(timeout=30_000)
        open_folder(page, "Stored configurations")
        wait_until(lambda: "could not be read and was left out" in _status(page), 20, "the bad list reported")
        assert _stored(v) == []
        page.close()


# ---------------------------------------------------------------------- frames and camera
def _red_blue(img: np.ndarray) -> tuple[int, int]:
    """Pixels of the DH arrows' red (x) and blue (z), shaded by the lights (grey grid and orange links left out)."""
    r, g, b = img[..., 0], img[..., 1], img[..., 2]
    return int(((r > 120) & (r - g > 80) & (r - b > 80)).sum()), int(((b > 120) & (b - r > 80)).sum())


def _settled(page, timeout: float = 20.0) -> np.ndarray:
    """The canvas left of the panel once three screenshots 0.5 s apart agree (the page has drawn the last change)."""
    last = _pixels(page.screenshot())[:, :600]
    agree = 0
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        time.sleep(0.5)
        now = _pixels(page.screenshot())[:, :600]
        agree = agree + 1 if (np.abs(now - last).sum(axis=-1) > 60).sum() < 20 else 0
        if agree >= 2:
            return now
        last = now
    raise AssertionError("the page kept changing")


def test_world_triad_frame_numbers_and_dh_frames(browser, docs_img: Path) -> None:
    with View("puma560", lang="en") as v:
        ro = v.panels.readouts
        page = open_page(browser, v.url, f"{v.robot.joint_names[0]} (°)")
        # the labelled world triad and a label per place where frames meet
        assert [n.text for n in ro.triad[1:4]] == ["x", "y", "z"]
        F = armkit.fk_frames(v.robot, v.q)
        shown = {k: node.text for k, node in enumerate(ro.numbers) if node.visible}
        assert shown == dict(frame_number_groups(F, 1e-6 * ro.reach_m / ro.s))
        for k in shown:
            assert np.allclose(ro.numbers[k].position, F[k, :3, 3] * v.robot.unit_scale)
        open_folder(page, "Frames and camera")
        v.panels.gizmo.visible = False        # its red and blue handles would count with the arrows
        v.set_q(np.zeros(6))
        client = next(iter(v.server.get_clients().values()))
        s, R = v.robot.unit_scale, v.robot.reach * v.robot.unit_scale
        # the middle of the frame origins, moved to the screen's right so that the arm is left of the panel;
        # from this close the arrows add 600-700 red and blue pixels (from the iso preset 150-250, too near the bar)
        look = armkit.fk_frames(v.robot, v.q)[:, :3, 3].mean(axis=0) * s + 0.35 * R * np.array([1, 1, 0]) / 2 ** 0.5
        client.camera.position = tuple(look + 1.2 * R * np.array([1, -1, 1]) / 3 ** 0.5)
        client.camera.look_at = tuple(look)
        before = _settled(page)
        # DH frames on: a node per frame, posed at fk_frames; drawn (red and blue arrows appear in the canvas)
        page.get_by_text("DH frames (x red, z blue)", exact=True).click()
        wait_until(lambda: len(ro.dh_nodes) == v.robot.n + 1, what="the DH nodes added")
        red0, blue0 = _red_blue(before)
        seen: dict[str, int] = {}

        def arrows_drawn() -> bool:
            seen["red"], seen["blue"] = _red_blue(_pixels(page.screenshot())[:, :600])
            return seen["red"] > red0 + 100 and seen["blue"] > blue0 + 100

        wait_until(arrows_drawn, 60, "red x and blue z arrows in the canvas")
        q = np.radians([10.0, -30.0, 40.0, 20.0, 30.0, -15.0])
        v.set_q(q)
        F = armkit.fk_frames(v.robot, q)
        for node, T in zip(ro.dh_nodes, F):
            assert np.allclose(node.position, T[:3, 3] * v.robot.unit_scale, atol=1e-12)
            R = rotation_from_wxyz(node.wxyz)
            assert np.allclose(R[:, 0], T[:3, 0], atol=1e-9) and np.allclose(R[:, 2], T[:3, 2], atol=1e-9)
        # off: the nodes are removed and the arrows' colours leave the picture
        v.set_q(np.zeros(6))
        page.get_by_text("DH frames (x red, z blue)", exact=True).click()
        wait_until(lambda: ro.dh_nodes == [], what="the DH nodes removed")

        def gone() -> bool:
            red, blue = _red_blue(_pixels(page.screenshot())[:, :600])
            return abs(red - red0) < 0.3 * (seen["red"] - red0) and abs(blue - blue0) < 0.3 * (seen["blue"] - blue0)

        wait_until(gone, 30, "the arrows gone from the canvas")
        # the picture in the docs: on again, from closer
        page.get_by_text("DH frames (x red, z blue)", exact=True).click()
        wait_until(lambda: len(ro.dh_nodes) == v.robot.n + 1, what="the DH nodes added again")
        _settled(page)
        page.screenshot(path=str(docs_img / "view-dh-frames.png"))
        # frame numbers and the triad can be hidden
        page.get_by_text("world triad", exact=True).click()
        wait_until(lambda: not any(n.visible for n in ro.triad), what="triad hidden")
        page.get_by_text(f"frame numbers {{0}} … {{{v.robot.n}}}", exact=True).click()
        wait_until(lambda: not any(n.visible for n in ro.numbers), what="numbers hidden")
        page.close()


def test_camera_presets_move_the_browser_camera(browser) -> None:
    with View("fighter", lang="en") as v:
        page = open_page(browser, v.url, "yaw (°)")
        client = next(iter(v.server.get_clients().values()))
        reports: list[tuple[np.ndarray, np.ndarray]] = []      # what the browser says its camera is
        client.camera.on_update(lambda cam: reports.append((np.array(cam.position), np.array(cam.look_at))))
        centre = np.asarray(shoulder_point(v.robot)) * v.robot.unit_scale
        open_folder(page, "Frames and camera")
        expected = {"front": (1.0, 0.0, 0.0), "side": (0.0, -1.0, 0.0), "top": (0.0, 0.0, 1.0),
                    "iso": (1.0, -1.0, 1.0)}

        def looks(d: np.ndarray) -> bool:
            if not reports:
                return False
            p, look = reports[-1]
            off = p - look
            return bool(np.allclose(look, centre, atol=1e-6)
                        and np.allclose(off / np.linalg.norm(off), d / np.linalg.norm(d), atol=2e-3))

        for name, d in expected.items():
            # a click that lands while the folder above still opens can be lost on a busy machine (a clean clone's
            # make test, 2026-12-04): a person clicks again; the camera must then reach the preset all the same
            for attempt in range(3):
                page.get_by_role("button", name=name, exact=True).click()
                try:
                    wait_until(lambda: looks(np.array(d)), 10, f"the browser's camera at the {name} preset")
                    break
                except AssertionError:
                    if attempt == 2:
                        raise
        page.close()


def test_reach_cloud_colour_bar(browser) -> None:
    with View("planar3", lang="en") as v:
        page = open_page(browser, v.url, "q1 (°)")
        open_folder(page, "Workspace")
        assert page.locator(".armkit-colour-bar").count() == 0
        tick(page, "reach cloud (colour: manipulability)", lambda: bool(v.panels.ws_cb.value))
        wait_until(lambda: page.locator(".armkit-colour-bar").count() == 1, 60, "the colour bar")
        ws = workspace(v.robot, samples=20_000, seed=0, manipulability=True,
                                                 scene=False if v.ik_scene is None else v.ik_scene)
        top = float(np.percentile(np.asarray(ws.manipulability), 99))
        bar = page.locator(".armkit-colour-bar").first
        assert math.isclose(float(bar.get_attribute("data-top")), top, rel_tol=1e-12)
        assert f"{top:.3g}" in bar.inner_text() and "dark is low" in bar.inner_text()
        img = _pixels(page.locator(".armkit-colour-bar-gradient").first.screenshot())
        mid = img.shape[0] // 2
        # viridis' published ends: #440154 (low) and #fde725 (high)
        assert np.all(np.abs(img[mid, 1] - [0x44, 0x01, 0x54]) <= 8), img[mid, 1]
        assert np.all(np.abs(img[mid, -2] - [0xfd, 0xe7, 0x25]) <= 8), img[mid, -2]
        page.get_by_text("reach cloud (colour: manipulability)").click()
        wait_until(lambda: page.locator(".armkit-colour-bar").count() == 0, what="the bar hidden with the cloud")
        page.close()


# ---------------------------------------------------------------------- Korean
def test_readouts_in_korean_and_after_the_language_switch(browser) -> None:
    with View("fighter", lang="ko") as v:
        page = open_page(browser, v.url, "관절")
        for text in ("T와 J", "좌표계와 카메라", "저장한 관절 자세"):
            page.get_by_text(text, exact=True).first.wait_for(timeout=10_000)
        assert page.locator("button.armkit-T-copy").first.inner_text() == "복사"
        open_folder(page, "좌표계와 카메라")
        for text in ("정면", "측면", "위", "등각"):
            page.get_by_role("button", name=text, exact=True).first.wait_for(timeout=20_000)
            assert page.get_by_role("button", name=text, exact=True).count() == 1, text
        assert v.panels.readouts.triad[-1].text == "월드"           # the world triad's label
        v.set_lang("en")        # the page's language list: one stored-configurations folder, in English
        page.get_by_text("Stored configurations", exact=True).first.wait_for(timeout=20_000)
        time.sleep(1.0)
        assert page.get_by_text("Stored configurations", exact=True).count() == 1
        assert page.get_by_text("저장한 관절 자세", exact=True).count() == 0
        assert page.locator("table.armkit-T").count() == 1
        page.close()


@pytest.mark.parametrize("text", ["x = [", 'unit = "m"\n', '[[configuration]]\nname = "a"\nq = [1, 2]\n',
                                  'angle_unit = "grad"\n', 'joints = ["a", "b", "c"]\n'])
def test_import_errors_are_templates_shown_in_korean(text):
    """A bad import names the problem in the page's language: the Korean comes from the catalogue, not from English."""
    from armkit.locale import translate
    from armkit.viz.view.readouts import parse_configurations_toml

    with pytest.raises(armkit.ViewError) as info:
        parse_configurations_toml(armkit.load("fighter"), text)
    ko = translate(info.value.template, "ko", **info.value.fields)
    assert re.search(r"[가-힣]", ko), ko
    assert ko != str(info.value)
    assert translate(info.value.template, "en", **info.value.fields) == str(info.value)
