# Shared by the Python module's tests (tests/python/, run by ctest under the interpreter the module
# was built for): the command line to compare with, from GANZFELD_CLI.
import json
import os
import subprocess

import pytest


class Cli:
    """`ganzfeld` as a user runs it: run(...) -> (exit code, stdout, stderr); json(...) parses."""

    def __init__(self, path):
        self.path = path

    def run(self, *args):
        p = subprocess.run([self.path, *map(str, args)], capture_output=True, text=True)
        return p.returncode, p.stdout, p.stderr

    def json(self, *args):
        code, out, err = self.run(*args, "--json")
        assert code == 0, err
        return json.loads(out)

    def refusal(self, *args):
        """The one-line message of a refusal (exit code 2), without the "ganzfeld: " prefix."""
        code, _, err = self.run(*args)
        assert code == 2, err
        assert err.startswith("ganzfeld: ") and err.count("\n") == 1, err
        return err[len("ganzfeld: "):].rstrip("\n")


@pytest.fixture(scope="session")
def cli():
    path = os.environ.get("GANZFELD_CLI")
    if not path:
        pytest.fail("GANZFELD_CLI must name the ganzfeld executable (ctest sets it)")
    return Cli(path)


def vector_text(v):
    """X,Y,Z as --i/--j take it: shortest round-trip decimals, so the CLI parses the same doubles."""
    return ",".join(repr(float(x)) for x in v)
