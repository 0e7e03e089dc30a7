// Linked with one of fe_server's layers whole and the layers above it only
// (CMakeLists.txt): it builds when the layer calls nothing below itself.
int main() { return 0; }
