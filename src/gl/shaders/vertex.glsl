// One point per patch; the geometry shader finds its record through gl_PrimitiveIDIn.
void main() {}
