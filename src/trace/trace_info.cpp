// Placeholder until the Embree renderer lands (issue 4).
namespace surftrace::trace { const char* traceInfo() { return "embree"; } }
