// plates: the compensation on/off plate test: the page (placeholder).
