"""Calls of the part-error models from the process operations for openapi_contract.py (placeholder)."""


def exercise(base, call):
    pass
