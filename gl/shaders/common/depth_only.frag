// Depth pre-pass: depth is all that is written.
void main() {}
