"""An operator's ERROR report. Run as a script or the UI runs it (bpy.ops),
an operator's ERROR report reaches the caller as RuntimeError("Error:
<report>"); an uncaught exception in the operator as RuntimeError("Error:
Python: Traceback ..."): a refusal must be the former."""
from lib.checks import check


class Reports:
    """Runs an operator and keeps what it reported."""

    def __init__(self, op, **kwargs):
        self.result, self.error = None, ""
        try:
            self.result = op(**kwargs)
        except RuntimeError as e:
            self.error = str(e).strip()

    def refused_with(self, exact):
        """An ERROR report whose text is exactly `exact` (after "Error: ")."""
        return self.error == "Error: " + exact

    def describe(self):
        return f"report '{self.error}'" if self.error else f"no ERROR report (result {self.result})"


def expect_report(op, exact, what, **kwargs):
    """The operator reports an ERROR of exactly the text `exact`, not a
    traceback. Returns its Reports."""
    r = Reports(op, **kwargs)
    check(r.refused_with(exact) and "Traceback" not in r.error,
          f"{what}: {r.describe()}" + ("" if r.refused_with(exact) else f"; expected '{exact}'"))
    return r


def expect_error(op, texts, what, **kwargs):
    """The operator reports an ERROR containing every text, not a Python
    traceback. Returns the message ("" when there was none)."""
    try:
        result = op(**kwargs)
    except RuntimeError as e:
        message = str(e)
        check(message.startswith("Error:") and "Traceback" not in message and
              all(t in message for t in texts), f"{what}: ERROR report '{message.strip()}'")
        return message
    check(False, f"{what}: expected an ERROR report, got {result}")
    return ""
