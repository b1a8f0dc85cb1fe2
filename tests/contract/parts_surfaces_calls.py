"""Calls of the surfaces: the CMM mirror correction operations for openapi_contract.py (placeholder)."""


def exercise(base, call):
    pass
