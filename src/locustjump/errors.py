"""The one exception the command line turns into a one-line message."""


class UserError(Exception):
    """Bad input from the user: the CLI prints it on one line and exits 2."""
