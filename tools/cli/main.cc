// Entry point of the d2vdb command; replaced by the sub-command dispatcher.
int main() { return 0; }
