"""``python -m persistri``: the ``persistri`` command (:mod:`persistri.impl.cli.main`), under the name ``persistri``."""

from persistri.impl.cli.main import main

if __name__ == "__main__":
    main(prog_name="persistri")
