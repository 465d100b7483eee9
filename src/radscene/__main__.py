"""``python -m radscene`` runs the command line."""

from radscene.cli import run

run()
