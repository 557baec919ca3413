"""The benchmark scripts (run as `python bench/NAME.py`); a package so that
the tests can import what they check (`pytest`'s `pythonpath` has the
repository's root)."""
