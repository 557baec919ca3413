import sys

from symsynth.cli import main

sys.exit(main())
