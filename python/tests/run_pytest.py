"""ctest's entry to the Python package's tests (python/CMakeLists.txt): pytest with these arguments.

pytest's exit code 5 (no test collected: an empty -k selection, every test deselected) and a Python
without pytest are reported to ctest as skipped (77, the test's SKIP_RETURN_CODE), never as a failure;
every other code is pytest's own (0 passed, 1 a test failed, ...)."""
import sys

SKIPPED = 77

try:
    import pytest
except ImportError:
    print("python package tests skipped: %s has no pytest (Debian: python3-pytest)" % sys.executable)
    sys.exit(SKIPPED)

code = pytest.main(["-p", "no:cacheprovider"] + sys.argv[1:])
if code == pytest.ExitCode.NO_TESTS_COLLECTED:
    print("python package tests: nothing collected (exit code 5), reported as skipped")
    sys.exit(SKIPPED)
sys.exit(int(code))
