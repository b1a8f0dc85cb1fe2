"""Calls of the turned parts: the four-diameter decomposition operations for openapi_contract.py (placeholder)."""


def exercise(base, call):
    pass
