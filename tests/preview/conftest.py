"""pytest set-up of the preview tests (run by ctest, see tests/CMakeLists.txt)."""

import sys
import pathlib

import pytest

sys.path.insert(0, str(pathlib.Path(__file__).parent))

from preview_harness import penumbra_cli  # noqa: E402

# ctest reports a run whose every test skipped as skipped (SKIP_RETURN_CODE), not passed.
SKIPPED_EXIT_CODE = 77


def pytest_sessionfinish(session, exitstatus):
    reporter = session.config.pluginmanager.get_plugin("terminalreporter")
    # A module skipped as a whole (no browser) leaves no test collected: pytest's exit code 5.
    if exitstatus in (pytest.ExitCode.OK, pytest.ExitCode.NO_TESTS_COLLECTED) and reporter is not None:
        stats = reporter.stats
        if stats.get("skipped") and not stats.get("passed") and not stats.get("failed"):
            session.exitstatus = SKIPPED_EXIT_CODE


@pytest.fixture(scope="session")
def cli():
    path = penumbra_cli()
    if not path:
        pytest.skip("the penumbra command was not found (set PENUMBRA_CLI)")
    return path
