"""``python -m balance`` runs the command line."""

from .cli import main

main()
