"""The Python test scripts' check counter: check(cond, what) counts a result
and reports a failure on stderr; done(name) prints the tally and exits 1 when
anything failed."""
import sys

_tally = {"passed": 0, "failed": 0}


def check(cond, what):
    if cond:
        _tally["passed"] += 1
    else:
        _tally["failed"] += 1
        print("FAIL:", what, file=sys.stderr)


def done(name):
    print("%s: %d passed, %d failed" % (name, _tally["passed"], _tally["failed"]))
    sys.exit(1 if _tally["failed"] else 0)
