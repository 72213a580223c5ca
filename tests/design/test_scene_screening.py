"""Per-spring limits by exchange (issue 29, item 2): a helical mesh's contact-stress limit has one row per spring
(slices x positions x tooth pairs); the scene hands Ipopt only the springs near the limit
(``spring_limit_screen``, :meth:`gearopt.nlp.problem.Problem.subject_to` ``screen``) and exchanges them as the
design moves. The reference is the same NLP with every spring a row: the same optimum, with the limit active."""

import dataclasses

import pytest

import gearopt as go
from gearopt.contact.ltca import ltca
from gearopt.design.scene import DesignVariable, Limit, LoadCase, Objective, Scene
from gearopt.design.scene_transcription import SCREEN_MIN_ELEMENTS

MESH = "crank-cam"
pytestmark = pytest.mark.filterwarnings("ignore::UserWarning")


def _solve(train, limit_MPa, screen):
    scene = Scene("screened stress", train=train, load_cases=[LoadCase("design", 300.0)],
                  variables=[DesignVariable(v, MESH) for v in ("tip_relief_1_um", "tip_relief_2_um")],
                  objectives=[Objective("ppte_um", MESH)],
                  limits=[Limit("max_contact_stress_MPa", MESH, upper=limit_MPa)],
                  ltca_options={"max_refinements": 0, "positions": 80, "spring_limit_screen": screen})
    built = scene.build()
    return built, built.solve()


def test_screened_spring_limit_gives_the_optimum_of_every_spring_with_fewer_rows():
    train = dataclasses.replace(go.load_default_train("spur"), helix_angle_deg=8.0)
    limit = 1.01 * ltca(train.pairs[MESH], 300.0).max_contact_stress_MPa    # binds: relief raises the peak
    full_built, full = _solve(train, limit, None)
    built, screened = _solve(train, limit, 0.2)
    for name, value in full.values.items():
        assert screened.values[name] == pytest.approx(value, rel=1e-6, abs=1e-6)
    stress = screened.quantities.query("quantity == 'max_contact_stress_MPa'")
    assert float(stress["value"].max()) == pytest.approx(limit, rel=1e-4)         # the limit is active
    rows, all_rows = built.transcription.problem.opti.ng, full_built.transcription.problem.opti.ng
    assert all_rows - rows >= SCREEN_MIN_ELEMENTS // 2                              # most springs held back
    assert float(stress["value"].max()) <= limit * (1.0 + 1e-5)     # every spring met (Ipopt tolerance)


def test_screening_on_a_pair_of_other_names(tmp_path):
    """Any train: the packaged minimal pair with its gears renamed, at an 8 deg helix (sliced): the screened NLP
    ends at the optimum of every spring's NLP with at most a fifth of its rows."""
    import re

    from gearopt.data import default_data_path, load_system, train_from_data

    text = (default_data_path().parent / "minimal_train.toml").read_text(encoding="utf-8")
    for old, new in {"pinion": "sun_gear", "wheel": "drum_gear"}.items():
        text = re.sub(rf"\b{old}\b", new, text)
    (tmp_path / "renamed.toml").write_text(text, encoding="utf-8")
    system = load_system(tmp_path / "renamed.toml")
    train = dataclasses.replace(train_from_data(system.data), helix_angle_deg=8.0)
    mesh = "sun_gear-drum_gear"
    limit = 1.01 * ltca(train.pairs[mesh], 100.0).max_contact_stress_MPa
    built, results = {}, {}
    for screen in (None, 0.2):
        scene = Scene("renamed", train=train, load_cases=[LoadCase("design", 100.0)],
                      variables=[DesignVariable(v, mesh) for v in ("tip_relief_1_um", "tip_relief_2_um")],
                      objectives=[Objective("ppte_um", mesh)],
                      limits=[Limit("max_contact_stress_MPa", mesh, upper=limit)], data=system,
                      ltca_options={"max_refinements": 0, "positions": 80, "spring_limit_screen": screen})
        built[screen] = scene.build()
        results[screen] = built[screen].solve()
    for name, value in results[None].values.items():
        assert results[0.2].values[name] == pytest.approx(value, rel=1e-6, abs=1e-6)
    assert 5 * built[0.2].transcription.problem.opti.ng <= built[None].transcription.problem.opti.ng
