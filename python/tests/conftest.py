"""One device for the whole suite, with the Khronos validation layer on: any error it
reports fails the run at the end."""

import os

import pytest

import tessera


@pytest.fixture(scope="session")
def device():
    device = tessera.Device(validation=True)
    yield device
    assert device.validation_errors() == []


def pytest_runtest_logreport(report):
    """Skipped tests go to the skip log `make test` prints at the end, by name and reason."""
    log = os.environ.get("TESSERA_SKIP_LOG")
    if log and report.skipped:
        reason = report.longrepr[2] if isinstance(report.longrepr, tuple) else report.longrepr
        with open(log, "a") as out:
            out.write(f"python/{report.nodeid}: {reason}\n")
