"""The surfaces: the CMM mirror correction pages in headless Chromium (placeholder)."""


def run(d, s, check, out):
    pass
