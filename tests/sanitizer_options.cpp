// The sanitizer runtime's settings, compiled into every executable of the debug-asan build (the
// test binaries and `wedge`), so that ctest, CI and a test binary run by hand behave alike: any
// report ends the process with a failure. Variables in the environment (ASAN_OPTIONS, ...) still
// override a setting for one run. The runtime looks these functions up by name at start-up.
#ifndef WEDGE_LSAN_SUPPRESSIONS
#error "WEDGE_LSAN_SUPPRESSIONS (the path of tests/lsan.supp) must be defined"
#endif

extern "C" {
// halt_on_error: stop at the first report (the build also has -fno-sanitize-recover=all);
// detect_leaks: LeakSanitizer at exit (on by default on x86-64 Linux; said here so it stays on).
const char* __asan_default_options() { return "halt_on_error=1:detect_leaks=1:abort_on_error=0"; }
const char* __ubsan_default_options() { return "halt_on_error=1:print_stacktrace=1"; }
// The suppression file holds only allocations of the OpenGL oracle (Mesa), each one explained.
const char* __lsan_default_options() { return "suppressions=" WEDGE_LSAN_SUPPRESSIONS ":print_suppressions=0"; }
}
