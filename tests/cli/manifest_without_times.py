#!/usr/bin/env python3
"""Prints a bake manifest with the fields that record wall-clock time removed
(statistics.*seconds*), keys sorted: what two equal bakes must agree on
byte for byte. Usage: manifest_without_times.py manifest.json"""
import json
import sys


def strip(value):
    if isinstance(value, dict):
        return {k: strip(v) for k, v in value.items() if "seconds" not in k}
    if isinstance(value, list):
        return [strip(v) for v in value]
    return value


manifest = json.load(open(sys.argv[1]))
manifest["statistics"] = strip(manifest.get("statistics", {}))
print(json.dumps(manifest, indent=2, sort_keys=True))
