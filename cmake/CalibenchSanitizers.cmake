# Sanitizer and fuzzing instrumentation, applied to every target of the project (third-party
# libraries from Debian stay uninstrumented: ASan still sees their heap through its interceptors).
#
# CALIBENCH_SANITIZE=ON      AddressSanitizer + UndefinedBehaviorSanitizer; any UB report is fatal
#                            (-fno-sanitize-recover), so a test that triggers one fails.
# CALIBENCH_BUILD_FUZZERS=ON libFuzzer coverage instrumentation for the libraries (clang only);
#                            fuzz/ links its targets with -fsanitize=fuzzer.
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
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined
                      -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
endif()
