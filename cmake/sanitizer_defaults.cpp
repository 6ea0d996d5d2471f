// The sanitizer runtime's default options, compiled into every executable of the sanitizer build
// (toolchains/host-asan.cmake sets ALE_SANITIZED; ale_executable adds this file), so that a test,
// a tool run by a test script and a binary started by hand behave alike without environment
// variables. ASAN_OPTIONS / UBSAN_OPTIONS / LSAN_OPTIONS still override single options.
//
// Every report ends the process with exit status 23: no test or tool expects that status (the
// sanitizers' default, 1, is what our tools return for bad input, so a CLI test expecting exit 1
// or a script checking for it would take a memory error for the expected failure).
// docs/architecture.md, "Tests and sanitizers".

extern "C" {

// AddressSanitizer (LeakSanitizer runs inside it at exit): leaks on, and a global constructor
// reading another translation unit's global before that one is initialised is reported.
__attribute__((visibility("default"), used)) const char* __asan_default_options() {
  return "detect_leaks=1:exitcode=23:check_initialization_order=1:strict_init_order=1";
}

// UndefinedBehaviorSanitizer: fatal (the code is built with -fno-sanitize-recover=undefined too),
// with the stack of the report.
__attribute__((visibility("default"), used)) const char* __ubsan_default_options() {
  return "print_stacktrace=1:halt_on_error=1:exitcode=23";
}

}  // extern "C"
