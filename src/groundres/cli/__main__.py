"""`python -m groundres.cli`: the same as the `groundres` command."""

from . import main

main()
