"""check() prints one line per check ("ok   " or "FAIL ") and counts the
failures; run_checks() runs a headless test's main() and exits with 1 when
any check failed or main() raised (its traceback printed)."""
import sys
import traceback

failures = []


def check(condition, what):
    print(("ok   " if condition else "FAIL ") + what, flush=True)
    if not condition:
        failures.append(what)
    return condition


def summary():
    """The closing line: how many checks failed."""
    text = f"{len(failures)} failure(s)" if failures else "all checks passed"
    print(text, flush=True)
    return text


def run_checks(main):
    """Runs main(); a crash of the test itself is a failure, with its
    traceback. Exits 0 only when every check passed."""
    try:
        main()
    except Exception:
        traceback.print_exc()
        failures.append("exception")
    summary()
    sys.exit(1 if failures else 0)
