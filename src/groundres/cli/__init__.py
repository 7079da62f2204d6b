"""Command line: parse, call the API, write and print, set the exit code.

Exit status: 0 on success, 2 on a bad case file or option (one readable
message, no traceback), 1 on any other failure. Set GROUNDRES_DEBUG=1 to see
tracebacks of unexpected failures.
"""

from __future__ import annotations

import os
import sys

import click

from . import cases, equations, phasors, run, simulate
from .common import UserError


class _Group(click.Group):
    def invoke(self, ctx):
        try:
            return super().invoke(ctx)
        except (click.ClickException, click.exceptions.Exit, click.Abort, SystemExit):
            raise
        except BrokenPipeError:  # output piped into a program that stopped reading
            sys.stderr.close()
            sys.exit(0)
        except Exception as err:  # noqa: BLE001 - the one place failures become exit codes
            from ..analysis import MethodError
            from ..config import CaseError
            from ..limits import ModelRangeError
            from ..transition import SpeedRangeError

            if isinstance(err, (CaseError, MethodError, ModelRangeError, SpeedRangeError)):
                raise UserError(str(err)) from None
            if os.environ.get("GROUNDRES_DEBUG"):
                raise
            click.echo(f"error: {type(err).__name__}: {err}", err=True)
            sys.exit(1)


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="groundres")
def main():
    """groundres: helicopter ground resonance from equations it derives itself.

    Run `groundres run` for the built-in default case, `groundres cases` for the
    shipped cases, `groundres run CASE.toml --out DIR` for your own.
    """


for _module in (run, simulate, phasors, cases, equations):
    main.add_command(_module.command)
