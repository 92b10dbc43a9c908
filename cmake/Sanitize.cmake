# DEEPSEA_SANITIZE: ASan + UBSan on everything we compile (flags set before any target exists, so
# the layers, the CLI and the tests all get them). UBSan is fatal (-fno-sanitize-recover=all) so
# that a report fails the test that triggered it; ASan reports leaks at exit (LSan, on by
# default on Linux). Third-party libraries (OpenVDB, OpenImageIO, ...) are Debian's, not
# instrumented: ASan still sees their heap through its malloc.
#
# DEEPSEA_FUZZ: clang only. The same build also instruments for libFuzzer
# (-fsanitize=fuzzer-no-link) and adds tests/fuzz, whose targets link -fsanitize=fuzzer, so that
# one build serves both the sanitizer test run and the fuzzers.
if(DEEPSEA_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "DEEPSEA_FUZZ needs clang (libFuzzer): -DCMAKE_CXX_COMPILER=clang++-14")
  endif()
  set(DEEPSEA_SANITIZE ON CACHE BOOL "" FORCE)
endif()

if(DEEPSEA_SANITIZE)
  set(_san -fsanitize=address,undefined -fno-sanitize-recover=all)
  add_compile_options(${_san} -fno-omit-frame-pointer -g)
  if(CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    # Third-party header code that UBSan reports (each entry says why), and no "loop not
    # vectorized" notes: the instrumentation defeats the runtime's `omp simd` loops.
    add_compile_options(
      -fsanitize-ignorelist=${PROJECT_SOURCE_DIR}/tests/sanitizers/ignorelist.txt
      -Wno-pass-failed)
  endif()
  add_link_options(${_san})
  if(DEEPSEA_FUZZ)
    add_compile_options(-fsanitize=fuzzer-no-link)
  endif()
endif()
