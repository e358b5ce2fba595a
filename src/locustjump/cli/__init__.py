"""``locustjump`` command line: thin wrappers over the library.

Every error a user can cause ends in one line on stderr and exit status 2;
Ctrl-C ends with status 130 and a line saying how to continue.
"""

from __future__ import annotations

import signal
import sys
from collections.abc import Sequence

from locustjump.cli.parser import build_parser
from locustjump.errors import UserError

#: how each command continues after an interruption
_CONTINUE = {
    "train": "rerun it with --resume to continue",
    "reproduce": "rerun the same command to continue",
}


def _os_error(e: OSError) -> str:
    where = f"{e.filename}: " if e.filename else ""
    return f"{where}{e.strerror or e}"


def main(argv: Sequence[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    parser = build_parser()
    # an unknown option before the command: name it (argparse would first
    # complain that the command is missing)
    if (
        argv
        and argv[0].startswith("-")
        and argv[0] not in ("-h", "--help", "--version")
    ):
        parser.error(f"unrecognized arguments: {argv[0]}")
    args = parser.parse_args(argv)
    previous = signal.signal(signal.SIGTERM, _interrupt)  # stop as on Ctrl-C
    try:
        return args.func(args)
    except (UserError, ValueError, ImportError) as e:
        print(f"locustjump: error: {e}", file=sys.stderr)
    except OSError as e:
        print(f"locustjump: error: {_os_error(e)}", file=sys.stderr)
    except (OverflowError, MemoryError) as e:
        print(
            f"locustjump: error: a number is too large for this command ({e})",
            file=sys.stderr,
        )
    except KeyboardInterrupt:
        how = _CONTINUE.get(args.command, "nothing was half-written")
        print(f"locustjump: interrupted ({how})", file=sys.stderr)
        return 130
    finally:
        signal.signal(signal.SIGTERM, previous)
    return 2


def _interrupt(signum, frame) -> None:
    raise KeyboardInterrupt


if __name__ == "__main__":
    sys.exit(main())
