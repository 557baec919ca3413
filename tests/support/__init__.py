"""What the tests share: scene builders, brute-force references, hypothesis
strategies, conformance suites for plugins.  Test files import from here,
never from one another."""
