// turned parts: the four-diameter decomposition: the page (placeholder).
