// surfaces: the CMM mirror correction: the page (placeholder).
