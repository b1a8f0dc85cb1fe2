"""Calls of the plates: the compensation on/off plate test operations for openapi_contract.py (placeholder)."""


def exercise(base, call):
    pass
