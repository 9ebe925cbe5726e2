// Placeholder until the GL path lands (issue 5).
namespace surftrace::gl { const char* glInfo() { return "gl"; } }
