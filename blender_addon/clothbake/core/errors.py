"""One error type for everything the add-on refuses, shaped like the C++
program's messages ("FILE: FIELD: message"), so the Blender layer can show it
in the UI as a report instead of a traceback."""


class ClothbakeError(Exception):
    """A refused input: names the file (may be empty) and the field or line."""

    def __init__(self, message, path="", field=""):
        self.path = str(path) if path else ""
        self.field = field
        self.message = message
        parts = [p for p in (self.path, field, message) if p]
        super().__init__(": ".join(parts))
