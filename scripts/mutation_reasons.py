"""What the equivalent mutants of ``scripts/mutation_equivalent.py`` and
``scripts/mutation_equivalent_evo.py`` share: the reasons given in both
layers, and the helpers that list a mutated construct's several mutants at
once."""

SORT_CASE = (
    "NumPy reads the sort kind case-insensitively (checked: the same order as "
    "'stable' where the default sort differs)"
)
ZIP = (
    "the lengths were compared just above: a row (or array) of another "
    "length has already raised"
)


def zip_strict(
    function: str, numbers: tuple[int, int, int], args: str, why: str
) -> dict[str, tuple[str, str]]:
    """The three mutants of ``zip(ARGS, strict=True)`` in ``function`` (their
    numbers in order: strict=None, the argument dropped, strict=False), which
    are equivalent where the lengths zipped cannot differ (``why``)."""
    texts = ("strict=None", f"zip({args}, )", "strict=False")
    return {
        f"{function}__mutmut_{n}": (text, why)
        for n, text in zip(numbers, texts, strict=True)
    }


def cast(
    function: str, numbers: tuple[int, int], dropped: str, why: str
) -> dict[str, tuple[str, str]]:
    """The two mutants of a ``dtype=`` cast in ``function`` (their numbers in
    order: ``dtype=None``, then the dtype dropped, whose mutated text is
    ``dropped``), equivalent where the data already has that type (``why``)."""
    texts = ("dtype=None", dropped)
    return {
        f"{function}__mutmut_{n}": (text, why)
        for n, text in zip(numbers, texts, strict=True)
    }


def alike(function: str, why: str, texts: dict[int, str]) -> dict[str, tuple[str, str]]:
    """Several mutants of ``function`` equivalent for one reason ``why``:
    ``texts`` maps each one's number to its mutated text."""
    return {f"{function}__mutmut_{n}": (text, why) for n, text in texts.items()}
