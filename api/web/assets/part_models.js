// part-error models from the process: the page (placeholder).
