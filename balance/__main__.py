"""``python -m balance`` runs the command line."""

from balance.cli import main

main()
