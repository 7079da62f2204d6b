"""Command line: parse, call the API, write and print, set the exit code.

Exit status: 0 on success, 2 on a bad case file or option (one readable
message, no traceback), 1 on any other failure, 130 on Ctrl-C and 143 on
SIGTERM (an output folder is then the one before the run, or the new one
complete if the signal came while it was being put in place). Set
GROUNDRES_DEBUG=1 to see tracebacks of unexpected failures.
"""

from __future__ import annotations

import os
import sys

import click

from ..errors import printable
from . import cases, compare, cycles, damper, equations, gallery, phasors, report, run, simulate, study
from .common import Terminated, UserError, interrupts, matplotlib_folder


class _Group(click.Group):
    def main(self, *args, standalone_mode=True, **kwargs):
        """As click's, but a usage mistake (an unknown option, a value that is no
        number) is one line naming the option and the help to read, exit 2."""
        if not standalone_mode:
            return super().main(*args, standalone_mode=False, **kwargs)
        try:
            rv = super().main(*args, standalone_mode=False, **kwargs)
        except click.exceptions.NoArgsIsHelpError as err:  # bare `groundres`: the help
            click.echo(err.format_message(), err=True)
            sys.exit(2)
        except click.UsageError as err:
            where = err.ctx.command_path if err.ctx is not None else "groundres"
            click.echo(printable(f"error: {err.format_message()} (see {where} --help)"), err=True)
            sys.exit(2)
        except click.ClickException as err:
            click.echo(printable(f"error: {err.format_message()}"), err=True)
            sys.exit(err.exit_code)
        except click.Abort:
            click.echo("aborted", err=True)
            sys.exit(1)
        sys.exit(rv if isinstance(rv, int) else 0)

    def parse_args(self, ctx, args):
        from datetime import UTC, datetime

        ctx.meta["groundres.argv"] = list(args)
        ctx.meta["groundres.started"] = datetime.now(UTC).isoformat(timespec="seconds")
        return super().parse_args(ctx, args)

    def invoke(self, ctx):
        try:
            with interrupts():
                return super().invoke(ctx)
        except KeyboardInterrupt as err:  # Ctrl-C or SIGTERM: outputs were left whole
            terminated = isinstance(err, Terminated)
            click.echo("terminated" if terminated else "interrupted", err=True)
            sys.exit(143 if terminated else 130)
        except (click.ClickException, click.exceptions.Exit, click.Abort, SystemExit):
            raise
        except BrokenPipeError:  # output piped into a program that stopped reading
            sys.stderr.close()
            sys.exit(0)
        except Exception as err:  # noqa: BLE001 - the one place failures become exit codes
            from ..errors import InputError

            if isinstance(err, InputError):  # (an input the user can mend: groundres.errors)
                raise UserError(str(err)) from None
            if os.environ.get("GROUNDRES_DEBUG"):
                raise
            click.echo(printable(f"error: {type(err).__name__}: {err}"), err=True)
            sys.exit(1)


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="groundres")
def main():
    """groundres: helicopter ground resonance from equations it derives itself.

    Run `groundres run` for the built-in default case, `groundres cases` for the
    shipped cases, `groundres run CASE.toml --out DIR` for your own.
    """
    matplotlib_folder()  # (before any command imports matplotlib)


for _module in (run, simulate, phasors, study, compare, report, gallery, cases, equations, damper, cycles):
    main.add_command(_module.command)
