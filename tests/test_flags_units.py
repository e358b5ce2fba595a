"""``cli.flags`` on a made-up parser: which option spells each setting."""

import argparse

from locustjump.cli.flags import options_by_setting, speller


def _parser():
    ap = argparse.ArgumentParser()
    ap.add_argument("run")  # positional: no option
    ap.add_argument("-o", "--out", "--out-dir")  # the longest long spelling
    # the longest spelling, not the last in order
    ap.add_argument("--solo", "--monolithic", dest="monolithic", action="store_true")
    ap.add_argument("--no-monolithic", dest="no_monolithic", action="store_true")
    ap.add_argument("-q", dest="quiet", action="store_true")  # no long form
    sub = ap.add_subparsers(dest="command")
    train = sub.add_parser("train")
    train.add_argument("--population", type=int)
    train.add_argument("--out-here", dest="out")  # a subcommand's replaces it
    study = sub.add_parser("study")
    study.add_argument("--seeds")
    return ap


def test_every_option_by_its_setting():
    assert options_by_setting(_parser()) == {
        "out": "--out-here",
        "monolithic": "--monolithic",
        "no_monolithic": "--no-monolithic",
        "population": "--population",
        "seeds": "--seeds",
    }


def test_a_setting_is_spelled_as_its_option():
    spell = speller(_parser())
    assert spell("population") == "--population"
    assert spell("population", 3) == "--population"
    assert spell("monolithic", False) == "--no-monolithic"  # turned off
    assert spell("monolithic", True) == "--monolithic"
    assert spell("monolithic") == "--monolithic"
    assert spell("seeds", False) == "--seeds"  # no --no-seeds: the option
    # not an option of this command line: the setting as the library names it
    assert spell("sigma") == "sigma"
    assert spell("sigma", 0.5) == "sigma=0.5"
    assert spell("sigma", False) == "sigma=False"


def test_a_setting_given_by_two_options_is_spelled_by_the_first():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out-dir", dest="out")
    ap.add_argument("--output-directory", dest="out")
    assert options_by_setting(ap) == {"out": "--out-dir"}
