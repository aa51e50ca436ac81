"""pytest set-up shared by the whole suite."""


def pytest_configure(config):
    """Import skmoor's warning classes before any test runs: pytest-xdist's controller
    rebuilds a warning a worker reports by importing the module that defines it, from one
    thread per worker; two of them importing skmoor.run at once can deadlock on the
    half-imported module (an INTERNALERROR). Imported here, once, they are found ready."""
    import skmoor.run.recorder  # noqa: F401
    import skmoor.run.simulate  # noqa: F401
