"""`python -m zedo_cli`: the `zedo` command without its console script."""

from .cli import main

main()
