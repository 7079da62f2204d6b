"""`groundres cases`: list the shipped cases or print one."""

from __future__ import annotations

import click

from .common import DEFAULT_CASE, fail_user, make_console


@click.command("cases")
@click.argument("name", required=False)
def command(name):
    """List the shipped cases, or print the case file NAME."""
    import tomllib

    from rich.table import Table

    from ..config import shipped_cases

    shipped = shipped_cases()
    console = make_console()
    if name:
        if name not in shipped:
            fail_user(f"case {name!r}: no such shipped case; choose one of {', '.join(shipped)}")
        click.echo(shipped[name], nl=False)
        return
    table = Table(title="Shipped cases (run with: groundres run NAME)", title_justify="left")
    table.add_column("name")
    table.add_column("title")
    for key, text in shipped.items():
        table.add_row(
            key + (" (default)" if key == DEFAULT_CASE else ""), tomllib.loads(text).get("title", "")
        )
    console.print(table)
