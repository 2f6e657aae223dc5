# RAYACCEL_SANITIZE=ON builds everything with AddressSanitizer and UndefinedBehaviorSanitizer;
# RAYACCEL_SANITIZE_THREAD=ON with ThreadSanitizer; RAYACCEL_BUILD_FUZZERS=ON adds libFuzzer's coverage
# instrumentation (Clang) to every object, so the fuzz targets of tests/fuzz see into the library.
# RAYACCEL_SANITIZE_FLAGS also compile the AVX kernels' sanitized objects of every tree (scripts/ci_asan_avx.sh).
set(RAYACCEL_SANITIZE_FLAGS -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
if(RAYACCEL_SANITIZE AND RAYACCEL_SANITIZE_THREAD)
  message(FATAL_ERROR "RAYACCEL_SANITIZE and RAYACCEL_SANITIZE_THREAD cannot be combined")
endif()
if(RAYACCEL_SANITIZE)
  add_compile_options(${RAYACCEL_SANITIZE_FLAGS})
  add_link_options(-fsanitize=address,undefined)
endif()
if(RAYACCEL_SANITIZE_THREAD)
  add_compile_options(-fsanitize=thread -fno-omit-frame-pointer)
  add_link_options(-fsanitize=thread)
endif()
if(RAYACCEL_BUILD_FUZZERS)
  add_compile_options(-fsanitize=fuzzer-no-link)
endif()
