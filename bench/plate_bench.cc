// Plate report benchmark (placeholder).
int main() { return 0; }
