// CMM import, mirror and report benchmark (placeholder).
int main() { return 0; }
