"""The ``rcb4hv`` command line."""
