"""``python -m rcb4hv``: the same command line as the ``rcb4hv`` script."""

from __future__ import annotations

from rcb4hv.cli.main import main

if __name__ == "__main__":
    main()
