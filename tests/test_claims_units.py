"""The verdicts of ``results.md`` (``present/stages``): each claim of the
paper against a stage's ``eval/metrics.json``, the number it is about, its
criterion, why a run misses it, and the composition question over seeds."""

import math

import pytest

from locustjump.present.stages import base, reporter_of
from locustjump.present.stages import getup as gu
from locustjump.present.stages import kick as ki
from locustjump.present.stages import return_legs as rl
from locustjump.present.stages import successive as su
from locustjump.tasks import Kick, behaviour_class


def test_a_claim_row_and_its_words():
    c = base.Claim("it jumps", "2x")
    assert c.row() == "| it jumps | 2x | not run yet | - |"
    done = base.Claim("it jumps", "2x", "1.5x", "no (>= 1.8x)")
    assert done.row() == "| it jumps | 2x | 1.5x | no (>= 1.8x) |"
    assert (base.yes(True), base.yes(False)) == ("**yes**", "no")
    assert base.fmt(None, unit="x") == "n/a" and base.fmt(1.234) == "1.23"
    assert base.fmt(1.0, ".1f", " m") == "1.0 m" and base.fmt(7, "d") == "7"
    assert base.fmt(float("inf")) == "inf"  # lower case, as every number


def test_the_default_reporter_claims_nothing():
    r = base.Reporter()
    assert r.claims({"metrics": {}}) == [] and r.report_section({}) == []
    assert r.across_seeds({}) == [] and r.headline == ("fitness",)


def test_every_behaviour_gets_its_reporter_or_its_bases():
    assert type(reporter_of("kick")) is ki.KickReporter
    assert type(reporter_of(Kick)) is ki.KickReporter
    assert type(reporter_of("kick-apex")) is ki.CeilingReporter
    assert type(reporter_of("composed")) is su.ComposedReporter
    assert type(reporter_of(behaviour_class("monolithic")())) is su.MonolithicReporter
    assert type(reporter_of("composed-height")) is su.ComposedReporter
    assert ki.CeilingReporter().claims({"metrics": {}}) == []


def test_a_reporter_is_registered_for_a_behaviour_class_only(monkeypatch):
    from locustjump.present import stages

    monkeypatch.setattr(stages, "_REPORTERS", dict(stages._REPORTERS))

    class Hop(Kick):
        name = "hop-test"

    mine = ki.KickReporter()
    stages.register_reporter(Hop, mine)
    assert reporter_of(Hop) is mine and reporter_of(Hop()) is mine
    assert reporter_of(Kick) is not mine
    for wrong in (Hop(), int, "kick"):
        with pytest.raises(TypeError, match=r" is not a Behaviour subclass$"):
            stages.register_reporter(wrong, mine)


def _kick(ratio, **more):
    m = {"apex_height_m": 1.5, "rules_first_apex_height_m": 0.8, **more}
    if ratio is not None:
        m["apex_height_ratio_to_rules"] = ratio
    return {"metrics": m}


@pytest.mark.parametrize(("ratio", "ok"), [(1.8, True), (1.79, False), (None, False)])
def test_the_kick_jumps_2x_as_high_by_at_least_1_8x(ratio, ok):
    (c,) = ki.KickReporter().claims(_kick(ratio))
    assert (c.value, c.ok) == (ratio, ok)
    assert c.verdict == ("**yes**" if ok else "no") + " (>= 1.8x)"
    want = "n/a" if ratio is None else f"{ratio:.2f}x"
    assert c.ours == f"{want} (1.50 m vs 0.80 m)"
    assert c.paper == "~2x" and c.measure == "apex / rule-based first apex (x)"
    assert c.why == ki.KICK_WHY and c.text == (
        "the evolved kick jumps about 2x as high as the rule-based first jump (Fig. 7)"
    )
    (blank,) = ki.KickReporter().claims(None)
    assert blank.ours is None and blank.text == c.text and blank.paper == "~2x"


def test_why_a_kick_misses_says_where_it_went():
    (c,) = ki.KickReporter().claims(_kick(1.2))
    assert c.reason == (
        "its highest point is 1.50 m: E = max dx*dz rewards distance as much as height"
    )
    full = _kick(1.2, distance_at_apex_m=2.345, takeoff_angle_deg=38.6)
    assert ki.KickReporter().claims(full)[0].reason == (
        "its highest point is 1.50 m, 2.35 m forward, after a take-off at 39 deg: "
        "E = max dx*dz rewards distance as much as height"
    )


def _getup(success, swept=None, n=180):
    rec = {"metrics": {"success": success}, "sweep_states": n}
    if swept is not None:
        rec["sweep_got_up"] = swept
    return rec


def test_getting_up_from_5_of_5_and_65_of_180():
    five, sweep = gu.GetUpReporter().claims(_getup([1, 1, 1, 1, 1], 65))
    assert five.text == "gets up from all 5 training states (Fig. 9)"
    assert sweep.text == "gets up from 65 of 180 sweep states"
    assert (five.ours, five.verdict, five.value, five.ok) == (
        "5 of 5",
        "**yes**",
        5,
        True,
    )
    assert five.paper == "5 of 5" and five.measure == "training states got up (of 5)"
    assert (sweep.ours, sweep.verdict, sweep.ok) == (
        "65 of 180",
        "**yes** (>= 65)",
        True,
    )
    assert (
        sweep.paper == "65 of 180" and sweep.measure == "sweep states got up (of 180)"
    )
    five, sweep = gu.GetUpReporter().claims(_getup([1, 0, 1, 1, 1], 64, n=90))
    assert (five.ours, five.verdict, five.ok) == ("4 of 5", "no", False)
    assert (sweep.ours, sweep.value, sweep.ok) == ("64 of 90", 64, False)
    assert sweep.measure == "sweep states got up (of 90)"
    _, unswept = gu.GetUpReporter().claims({"metrics": {"success": [1] * 5}})
    assert (unswept.ours, unswept.ok, unswept.verdict) == (
        "n/a of 180",
        False,
        "no (>= 65)",
    )
    blank = gu.GetUpReporter().claims(None)
    assert [c.ours for c in blank] == [None, None]
    assert [c.paper for c in blank] == ["5 of 5", "65 of 180"]
    assert [c.text for c in blank] == [five.text, sweep.text]


def _legs(final, start=None):
    m = {"final_error_deg": final}
    if start is not None:
        m["start_error_deg"] = start
    return {"metrics": m}


def test_the_legs_return_within_5_deg():
    final = {"hip_l": 1.0, "knee_l": 5.0, "hip_r": 2.0, "knee_r": 0.5}
    (c,) = rl.ReturnLegsReporter().claims(_legs(final))
    assert (c.value, c.ok, c.ours) == (5.0, True, "largest final error 5.00 deg")
    assert c.verdict == "**yes** (every joint within 5 deg)"
    assert c.why == rl.RETURN_LEGS_WHY and c.paper == "yes"
    assert c.text == "the legs return to the ready posture (Fig. 10)"
    assert c.measure == "largest final joint error (deg)"
    (c,) = rl.ReturnLegsReporter().claims(_legs({**final, "hip_r": 5.01}))
    assert (c.ok, c.verdict) == (False, "no (every joint within 5 deg)")
    (blank,) = rl.ReturnLegsReporter().claims(None)
    assert blank.ours is None and blank.text == c.text


def test_why_the_legs_miss_names_the_joints_off_phi():
    final = {"hip_l": 1.0, "knee_l": 7.5, "hip_r": 39.76, "knee_r": 4.9}
    start = {"knee_l": 20.0, "hip_r": 10.0}
    (c,) = rl.ReturnLegsReporter().claims(_legs(final, start))
    assert c.reason == (
        "hip_r ends 39.76 deg from phi, from 10.00 deg at the start (it moved "
        "away); knee_l ends 7.50 deg from phi, from 20.00 deg at the start; "
        "hip_l, knee_r end within 4.90 deg: the network has not learnt to bring "
        "hip_r and knee_l back"
    )
    (c,) = rl.ReturnLegsReporter().claims(
        _legs({"hip_l": 6.0, "knee_l": 1.0}, {"hip_l": 7.0})
    )
    assert c.reason == (
        "hip_l ends 6.00 deg from phi, from 7.00 deg at the start; knee_l ends within "
        "1.00 deg: the network has not learnt to bring hip_l back"
    )
    # by the largest error first; 5 deg itself is within; no farther: not "away"
    final = {"hip_l": 10.0, "knee_l": 5.0, "knee_r": 30.0}
    (c,) = rl.ReturnLegsReporter().claims(_legs(final, {"hip_l": 10.0}))
    assert c.reason == (
        "knee_r ends 30.00 deg from phi; hip_l ends 10.00 deg from phi, from 10.00 "
        "deg at the start; knee_l ends within 5.00 deg: the network has not learnt "
        "to bring knee_r and hip_l back"
    )
    (c,) = rl.ReturnLegsReporter().claims(_legs({"hip_l": 6.0}))
    assert c.reason == (
        "hip_l ends 6.00 deg from phi: the network has not learnt to bring hip_l back"
    )


def _composed(jumps, ratios, **more):
    m = {"jumps": jumps, "apex_ratios_to_rules": ratios,
         "rules_mean_apex_height_m": 0.4, **more}  # fmt: skip
    return {"metrics": m}


@pytest.mark.parametrize(
    ("jumps", "ratios", "ok", "low"),
    [
        (2, [2.5, 2.01], True, 2.01),
        (2, [2.5, 2.0], False, 2.0),  # more than 2x, not 2x
        (1, [3.0], False, 3.0),  # one jump is not successive jumping
        (3, [], False, None),
    ],
)
def test_every_composed_jump_more_than_2x_as_high(jumps, ratios, ok, low):
    (c,) = su.ComposedReporter().claims(_composed(jumps, ratios))
    assert (c.value, c.ok) == (low, ok)
    assert c.verdict == ("**yes**" if ok else "no") + " (>= 2 jumps, each > 2x)"
    said = "nothing to compare" if low is None else f"smallest ratio {low:.2f}x"
    n = f"{jumps} jump" + ("s" if jumps != 1 else "")
    assert c.ours == f"{n}, {said} (rule-based mean apex 0.40 m)"
    assert c.paper == "> 2x at every jump" and c.why == su.COMPOSED_WHY
    assert c.text == (
        "every composed jump is more than 2x as high as the rule-based jumps (Fig. 12)"
    )
    assert c.measure == "smallest jump / rule-based mean apex (x)"
    assert c.reason == su._composed_reason(_composed(jumps, ratios)["metrics"])
    assert c.reason.startswith(n)
    (blank,) = su.ComposedReporter().claims(None)
    assert blank.ours is None and blank.text == c.text


def test_a_composed_record_without_ratios_has_nothing_to_compare():
    rec = {"metrics": {"jumps": 0}}
    (c,) = su.ComposedReporter().claims(rec)
    assert c.value is None and c.ours.startswith("0 jumps, nothing to compare (")
    assert c.ours.endswith("rule-based mean apex n/a)")


@pytest.mark.parametrize(
    ("metrics", "reason"),
    [
        ({"jumps": 0}, "the composed controller never jumps"),
        (
            {"jumps": 0, "final_up_z": -0.5,
             "selected_steps": {"kick": 0, "getup": 0, "return-legs": 3000}},
            "the composed controller never jumps (the switcher selects return-legs "
            "for all of the 3000 steps); it never selects kick or getup, and it "
            "ends on its back",
        ),
        (
            {"jumps": 0, "final_up_z": 0.0,
             "selected_steps": {"kick": 10, "getup": 20, "return-legs": 30}},
            "the composed controller never jumps (the switcher selects kick 10, "
            "getup 20 and return-legs 30 of the 60 steps)",
        ),
        (
            {"jumps": 3, "apex_heights_m": [0.5, 1.234, 0.9],
             "selected_steps": {"kick": 5, "getup": 0, "return-legs": 7}},
            "3 jumps, the highest 1.23 m (the switcher selects kick 5 and "
            "return-legs 7 of the 12 steps)",
        ),
        ({"jumps": 1, "apex_heights_m": []}, "1 jump"),
        (
            {"jumps": 2, "selected_steps": {"kick elite 3": 3000, "getup": 0}},
            "2 jumps (the switcher selects kick elite 3 for all of the 3000 steps)",
        ),
    ],
)  # fmt: skip
def test_why_a_composed_controller_misses(metrics, reason):
    assert su._composed_reason(metrics) == reason


def _stage(fitness, evaluations=100, **m):
    metrics = {"fitness": fitness, "mean_height_m": 0.1234, "jumps": 4,
               "distance_m": 1.5, "overturned": 2, "recovered": 1, **m}  # fmt: skip
    return {"metrics": metrics, "evaluations": evaluations, "fitness": fitness}


def test_does_composition_help_on_one_seed():
    mono = su.MonolithicReporter()
    stages = {s: _stage(0, 100) for s in ("kick", "getup", "return-legs")}
    stages |= {"composed": _stage(900.0, 50), "monolithic": _stage(1200.0, 350)}
    assert mono.report_section(stages) == [
        "## Beyond the paper: does composition help?",
        "",
        "One 9-10-4 network evolved directly on the composed task (same start, "
        "3000 steps, same fitness E: Eq. 4, on a terrain with its progress "
        "term) with as many genome evaluations as the four stages of the "
        "composed controller together:",
        "",
        "| controller | fitness E (m x steps) | mean height (m) | jumps | "
        "distance (m) | overturned / recovered | evaluations |",
        "| --- | --- | --- | --- | --- | --- | --- |",
        "| composed (3 frozen + switcher) | 900.0 | 0.123 | 4 | 1.50 | 2 / 1 | 350 |",
        "| monolithic | 1200.0 | 0.123 | 4 | 1.50 | 2 / 1 | 350 |",
        "",
        "On this seed at this budget the composed controller scores below the "
        "monolithic one: its E is 0.75x the monolithic one's (one seed: no "
        "evidence either way; docs/science.md compares seeds).",
        "",
    ]

    def verdict(composed: float, monolithic: float) -> str:
        stages["composed"], stages["monolithic"] = _stage(composed), _stage(monolithic)
        return mono.report_section(stages)[-2].split(" scores ")[1].split(" (one")[0]

    assert (
        verdict(1200.5, 1200.0)
        == "above the monolithic one: its E is 1.00x the monolithic one's"
    )
    assert (
        verdict(7.0, 7.0)
        == "below the monolithic one: its E is 1.00x the monolithic one's"
    )
    assert (
        verdict(3.0, 0.5)
        == "above the monolithic one: its E is 6.00x the monolithic one's"
    )
    assert (
        verdict(3.0, 0.0)
        == "above the monolithic one: its E is n/a the monolithic one's"
    )
    missing = mono.report_section({"composed": stages["composed"]})
    assert missing == [
        "## Beyond the paper: does composition help?",
        "",
        "Needs the composed and the monolithic stages (not run yet: monolithic).",
        "",
    ]
    assert mono.report_section({})[2].endswith("(not run yet: composed, monolithic).")


def test_does_composition_help_over_seeds():
    mono = su.MonolithicReporter()
    seeds = {
        0: {"composed": {"fitness": 300.0}, "monolithic": {"fitness": 100.0}},
        1: {"composed": {"fitness": 50.0}, "monolithic": {"fitness": 200.0}},
        2: {"composed": {"fitness": 10.0}, "monolithic": {"fitness": 0.0}},
        3: {"composed": {"fitness": 10.0}},  # not both yet: left out
    }
    assert mono.across_seeds(seeds) == [
        "## Beyond the paper: does composition help?",
        "",
        "| seed | composed E | monolithic E | composed / monolithic |",
        "| --- | --- | --- | --- |",
        "| 0 | 300.0 | 100.0 | 3.00x |",
        "| 1 | 50.0 | 200.0 | 0.25x |",
        "| 2 | 10.0 | 0.0 | nanx |",
        "",
        "Composition beats the monolithic network in 2 of 3 seeds; median ratio "
        "1.62x; two-sided sign test over the seeds p = 1.",
        "",
    ]
    assert mono.across_seeds({3: seeds[3]}) == [
        "## Beyond the paper: does composition help?",
        "",
        "No seed has both the composed and the monolithic stage yet.",
        "",
    ]
    tie = {
        0: {"composed": {"fitness": 2.0}, "monolithic": {"fitness": 0.5}},
        1: {"composed": {"fitness": 4.0}, "monolithic": {"fitness": 4.0}},
    }
    lines = mono.across_seeds(tie)
    assert lines[4:6] == ["| 0 | 2.0 | 0.5 | 4.00x |", "| 1 | 4.0 | 4.0 | 1.00x |"]
    assert lines[-2].startswith(
        "Composition beats the monolithic network in 1 of 2 seeds"
    )
    nothing = mono.across_seeds({2: seeds[2]})
    assert "median ratio n/a;" in nothing[-2]


@pytest.mark.parametrize(
    ("wins", "n", "p"),
    [(0, 5, 2 / 32), (5, 5, 2 / 32), (1, 5, 12 / 32), (2, 4, 1.0), (7, 10, 0.34375)],
)
def test_the_sign_test(wins, n, p):
    assert su.sign_test(wins, n) == pytest.approx(p)
    assert su.sign_test(wins, n) == su.sign_test(n - wins, n)


def test_the_sign_test_is_exact():
    # 0 of 20: 2 * 2**-20 exactly
    assert su.sign_test(0, 20) == 2.0 * 2.0**-20 and math.isclose(
        su.sign_test(10, 20), 1.0
    )
