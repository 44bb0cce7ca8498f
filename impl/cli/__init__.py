"""The ``persistri`` command line (``persistri --help``)."""
