# Sanitizer and fuzzing instrumentation, applied to every target of the project (third-party
# libraries from Debian stay uninstrumented: ASan still sees their heap through its interceptors).
#
# CALIBENCH_SANITIZE=ON      AddressSanitizer + UndefinedBehaviorSanitizer; any UB report is fatal
#                            (-fno-sanitize-recover), so a test that triggers one fails.
# CALIBENCH_BUILD_FUZZERS=ON libFuzzer's edge coverage for every target (clang only), ASan + UBSan
#                            with it; fuzz/ links its targets with -fsanitize=fuzzer. One build
#                            (preset asan) holds the tests and the fuzzers: the edge counters
#                            (inline-8bit-counters, pc-table) cost the tests little; comparison
#                            tracing (trace-cmp, in -fsanitize=fuzzer-no-link) would put a call on
#                            every comparison of the numeric code, and the YAML fuzzers get their
#                            keywords from their dictionaries instead (fuzz/*.dict).
# Eigen stops trusting malloc's 16-byte alignment under __SANITIZE_ADDRESS__ and switches to its
# own aligned malloc (pointer offset by 16). Ceres from Debian is built without ASan and frees with
# plain free(): an Eigen matrix allocated in our code and freed in Ceres (or the reverse) is then a
# bad free. glibc's and ASan's malloc both align to 16 on x86-64, so we restore Eigen's default.
if(CALIBENCH_SANITIZE OR CALIBENCH_BUILD_FUZZERS)
  add_compile_definitions(EIGEN_MALLOC_ALREADY_ALIGNED=1)
endif()

if(CALIBENCH_SANITIZE)
  set(calibench_sanitize_flags -fsanitize=address,undefined -fno-sanitize-recover=undefined
                               -fno-omit-frame-pointer)
  add_compile_options(${calibench_sanitize_flags})
  add_link_options(-fsanitize=address,undefined)
endif()

if(CALIBENCH_BUILD_FUZZERS)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "CALIBENCH_BUILD_FUZZERS needs clang (CXX=clang++): libFuzzer is clang's")
  endif()
  add_compile_options(-fsanitize-coverage=inline-8bit-counters,pc-table)
  if(NOT CALIBENCH_SANITIZE)
    add_compile_options(-fsanitize=address,undefined -fno-sanitize-recover=undefined
                        -fno-omit-frame-pointer)
    add_link_options(-fsanitize=address,undefined)
  endif()
endif()
