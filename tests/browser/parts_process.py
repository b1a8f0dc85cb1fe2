"""The part-error models from the process pages in headless Chromium (placeholder)."""


def run(d, s, check, out):
    pass
