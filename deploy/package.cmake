# Install layout and the Debian package (docs/operations.md).
