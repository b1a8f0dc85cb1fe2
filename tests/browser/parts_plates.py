"""The plates: the compensation on/off plate test pages in headless Chromium (placeholder)."""


def run(d, s, check, out):
    pass
