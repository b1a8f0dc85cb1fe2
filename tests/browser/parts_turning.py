"""The turned parts: the four-diameter decomposition pages in headless Chromium (placeholder)."""


def run(d, s, check, out):
    pass
