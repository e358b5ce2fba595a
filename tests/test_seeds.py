"""Seeds as a user writes them (``--seeds``, a study file's ``seeds``;
``runs/multiseed.py``'s ``parse_seeds``) stated exactly: each form, each
refusal's words and each bound at its edge. (``tests/test_multiseed.py``
tries them through ``reproduce --seeds``.)"""

import pytest

from locustjump.runs.multiseed import MAX_SEEDS, parse_seeds

TOP = 2**63 - 1


@pytest.mark.parametrize(
    "text, seeds",
    [
        ("0-3", [0, 1, 2, 3]),
        ("5", [5]),
        ("3-3", [3]),
        ("0,3,7", [0, 3, 7]),
        ("7,0", [7, 0]),  # in the order given
        (" 0 - 1 , 4 ", [0, 1, 4]),
        ("9-10,2", [9, 10, 2]),
        (str(TOP), [TOP]),
        (f"{TOP - 1}-{TOP}", [TOP - 1, TOP]),
        ("007", [7]),
    ],
)
def test_the_forms_of_seeds(text, seeds):
    assert parse_seeds(text) == seeds


@pytest.mark.parametrize("part", ["", "-3", "0-", "a-b", "1-2-3", "1.5", "+2"])
def test_what_is_not_a_seed_or_a_range(part):
    text = f"0,{part}"
    with pytest.raises(ValueError) as e:
        parse_seeds(text)
    assert str(e.value) == (
        f"{text!r}: expected seeds like 0-9 or 0,3,7 (non-negative integers and "
        f"ranges), not {part.replace(' ', '')!r}"
    )


@pytest.mark.parametrize(
    "text, message",
    [
        ("3-1", "the range 3-1 is empty"),
        ("0,3-1", "the range 3-1 is empty"),
        (str(TOP + 1), f"a seed must be an integer in [0, 2**63-1], not {TOP + 1}"),
        (f"{TOP}-{TOP + 1}",
         f"a seed must be an integer in [0, 2**63-1], not {TOP + 1}"),
        ("5,3-5", "seed 5 is given twice"),
        ("4,3,4,3", "seed 3 is given twice"),
        ("0-1000", "more than 1000 seeds"),
        ("0-499,500-1000", "more than 1000 seeds"),
        ("2000,0-999", "more than 1000 seeds"),
    ],
)  # fmt: skip
def test_each_refusal_names_what_is_wrong(text, message):
    with pytest.raises(ValueError) as e:
        parse_seeds(text)
    assert str(e.value) == f"{text!r}: {message}"


def test_a_thousand_seeds_and_no_more():
    assert MAX_SEEDS == 1000
    assert parse_seeds("0-999") == list(range(1000))
    assert parse_seeds("0-499,500-999") == list(range(1000))
    seeds = parse_seeds("1000,0-998")
    assert seeds[:2] == [1000, 0] and len(seeds) == 1000
