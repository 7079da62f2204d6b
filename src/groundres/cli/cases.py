"""`groundres cases`: list the shipped cases or print one."""

from __future__ import annotations

import click

from ..errors import shown
from .common import DEFAULT_CASE, fail_user, make_console, plain


@click.command("cases")
@click.argument("name", required=False)
def command(name):
    """List the shipped cases, or print the case file NAME."""
    import tomllib

    from ..model.casefile import shipped_cases
    from .printout import simple_table

    shipped = shipped_cases()
    console = make_console()
    if name is not None:
        if name not in shipped:
            fail_user(f"case {shown(name)}: no such shipped case; choose one of {', '.join(shipped)}")
        click.echo(shipped[name], nl=False)
        return
    table = simple_table(f"Shipped cases (run with: groundres run NAME; the default is {DEFAULT_CASE})")
    table.add_column("name")
    table.add_column("title")
    for key, text in shipped.items():
        table.add_row(key, plain(tomllib.loads(text).get("title", "")))
    console.print(table)
