"""Issue 24, item 8: the quick, Hypothesis-driven part of the fuzz and corruption suite (in ``make test``).

The generators and judges are those of the long run (``tests/hardening/fuzz_long.py``, ``make fuzz``):
corrupted reachability stores, mutated URDF and scene files, mutated CLI arguments of the commands
added since the last round. Every case must end in ``ok`` or ``clean error`` (see fuzz_long's
docstring for the classes). Derandomised and bounded: the file runs in well under a minute.

The findings of the first runs are regression tests at the end (an edited grid in a store used to open
silently and answer for other places, or end ``reach query`` in numpy's LinAlgError).
"""

from __future__ import annotations

import json
import random
import shutil
from collections import Counter
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import fuzz_long as F

SETTINGS = dict(derandomize=True, deadline=None, database=None, print_blob=True,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


@pytest.fixture(scope="module")
def fuzz_root(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("fuzz")


@pytest.fixture(scope="module")
def store_fuzz(fuzz_root: Path) -> F.StoreFuzz:
    return F.StoreFuzz(fuzz_root, bound=20.0)      # builds the tiny planar2 map once (about a second)


SEEN: dict[str, Counter[str]] = {s: Counter() for s in F.SURFACES}
"""Outcomes per surface in this run (printed by test_outcome_table with ``-s``)."""


def _run(surface: str, fuzz: object, rnd: random.Random, work: Path) -> tuple[str, str]:
    outcome, detail = F.run_case(fuzz, rnd, _fresh(work))
    SEEN[surface][outcome] += 1
    return outcome, detail


def _fresh(path: Path) -> Path:
    if path.exists():
        shutil.rmtree(path)
    path.mkdir(parents=True)
    return path


# ---------------------------------------------------------------------------------------------- a. stores
@settings(max_examples=60, **SETTINGS)
@given(rnd=st.randoms(use_true_random=False))
def test_corrupted_store_is_the_original_or_refused(store_fuzz: F.StoreFuzz, rnd: random.Random) -> None:
    outcome, detail = _run("store", store_fuzz, rnd, store_fuzz.root / "work-store")
    assert outcome in (F.OK, F.CLEAN), f"{outcome}: {detail}"


def test_the_original_store_is_untouched(store_fuzz: F.StoreFuzz) -> None:
    assert F.tree(store_fuzz.path) == store_fuzz.orig_tree


# ---------------------------------------------------------------------------------------------- b. files
@pytest.fixture(scope="module")
def urdf_fuzz() -> F.UrdfFuzz:
    return F.UrdfFuzz(bound=20.0)


@pytest.fixture(scope="module")
def scene_fuzz() -> F.SceneFuzz:
    return F.SceneFuzz(bound=20.0)


@settings(max_examples=80, **SETTINGS)
@given(rnd=st.randoms(use_true_random=False))
def test_mutated_urdf_loads_or_raises_an_armkit_error(urdf_fuzz: F.UrdfFuzz, fuzz_root: Path,
                                                     rnd: random.Random) -> None:
    outcome, detail = _run("urdf", urdf_fuzz, rnd, fuzz_root / "work-urdf")
    assert outcome in (F.OK, F.CLEAN), f"{outcome}: {detail}"


@settings(max_examples=60, **SETTINGS)
@given(rnd=st.randoms(use_true_random=False))
def test_mutated_scene_loads_or_raises_an_armkit_error(scene_fuzz: F.SceneFuzz, fuzz_root: Path,
                                                      rnd: random.Random) -> None:
    outcome, detail = _run("scene", scene_fuzz, rnd, fuzz_root / "work-scene")
    assert outcome in (F.OK, F.CLEAN), f"{outcome}: {detail}"


@pytest.mark.parametrize("text", [
    "[[shapes]]\ntype = []\n",                                  # was TypeError: unhashable type: 'list'
    "[[shapes]]\ntype = {a = 1}\n",
    "unit = " + "[" * 500 + "]" * 500 + "\n",                   # was RecursionError from tomllib
    "[[shapes]]\ntype = \"box\"\ncenter = " + "[" * 500 + "]" * 500 + "\n",
])
def test_scene_findings_of_the_fuzzer_are_clean_errors(tmp_path: Path, text: str) -> None:
    from armkit.collision.files import load_scene
    from armkit.errors import SceneFileError

    p = tmp_path / "scene.toml"
    p.write_text(text)
    with pytest.raises(SceneFileError):
        load_scene(p)


# ---------------------------------------------------------------------------------------------- c. CLI
@pytest.fixture(scope="module")
def cli_fuzz(store_fuzz: F.StoreFuzz, fuzz_root: Path) -> F.CliFuzz:
    return F.CliFuzz(fuzz_root / "cli", store_fuzz.path, bound=30.0, heavy=False)


@settings(max_examples=60, **SETTINGS)
@given(rnd=st.randoms(use_true_random=False))
def test_mutated_cli_arguments_exit_0_1_2_without_traceback(cli_fuzz: F.CliFuzz, fuzz_root: Path,
                                                            rnd: random.Random) -> None:
    outcome, detail = _run("cli", cli_fuzz, rnd, fuzz_root / "work-cli")
    assert outcome in (F.OK, F.CLEAN), f"{outcome}: {detail}"


def test_the_view_stub_is_restored(cli_fuzz: F.CliFuzz) -> None:
    import armkit.viz.view as view_pkg

    assert view_pkg.view is not F._stub_view


def test_outcome_table() -> None:
    """The classes seen above, per surface (``pytest -s`` shows it; the property tests assert)."""
    cols = F.OUTCOMES
    print("\n" + f"{'surface':<8}" + "".join(f"{o:>14}" for o in cols))
    for s, c in SEEN.items():
        print(f"{s:<8}" + "".join(f"{c[o]:>14}" for o in cols))


# ---------------------------------------------------------------------------------------------- findings, fixed
def _edit_grid(store: Path, dst: Path, **grid) -> Path:
    c = dst / "edited.zarr"
    shutil.copytree(store, c)
    doc = json.loads((c / "zarr.json").read_text())
    doc["attributes"]["grid"].update(grid)
    (c / "zarr.json").write_text(json.dumps(doc))
    return c


@pytest.mark.parametrize("change", [{"lo": [-0.5, -0.05, -1.65]}, {"resolution": 0.2},
                                    {"T_world_A": [[1, 0, 0, 0.4], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]},
                                    {"T_world_A": [[0, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]},
                                    {"lo": [False, -0.05, -1.65]}])
def test_edited_grid_is_refused(store_fuzz: F.StoreFuzz, tmp_path: Path, change: dict) -> None:
    from armkit.errors import LimitError, MapFileError
    from armkit.reach import ReachabilityMap

    c = _edit_grid(store_fuzz.path, tmp_path, **change)
    with pytest.raises((MapFileError, LimitError)):
        ReachabilityMap.open(c)
    code, out, exc = F.cli(["reach", "query", str(c), "0.3", "0", "0"], 30)
    assert code == 2 and exc is None, out      # the original answers 1 (0.3 m is inside the 2R arm's hole)
