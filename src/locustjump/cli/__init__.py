"""``locustjump`` command line: thin wrappers over the library."""

from __future__ import annotations

import sys
from collections.abc import Sequence

from locustjump.cli.parser import build_parser
from locustjump.errors import UserError


def main(argv: Sequence[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except (UserError, ValueError, ImportError) as e:
        print(f"locustjump: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(
            "locustjump: interrupted (a run continues with --resume)", file=sys.stderr
        )
        return 130


if __name__ == "__main__":
    sys.exit(main())
