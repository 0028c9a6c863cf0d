# Sanitizer builds of our own targets (scripts/test.sh --sanitize and --tsan, scripts/fuzz.sh).
# ThreadSanitizer cannot share a process with AddressSanitizer, so the two options exclude each
# other. PENSIGHT_FUZZ adds libFuzzer's coverage instrumentation to the ASan+UBSan build and builds
# the fuzz targets (fuzz/); it needs clang.
option(PENSIGHT_SANITIZE "Build with AddressSanitizer and UndefinedBehaviorSanitizer" OFF)
option(PENSIGHT_TSAN "Build with ThreadSanitizer" OFF)
option(PENSIGHT_FUZZ "Build the libFuzzer targets (clang; implies PENSIGHT_SANITIZE)" OFF)
if(PENSIGHT_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "PENSIGHT_FUZZ needs clang (libFuzzer): configure with "
                        "-DCMAKE_CXX_COMPILER=clang++ -DCMAKE_C_COMPILER=clang, as scripts/fuzz.sh does")
  endif()
  set(PENSIGHT_SANITIZE ON CACHE BOOL "" FORCE)
endif()
if(PENSIGHT_SANITIZE AND PENSIGHT_TSAN)
  message(FATAL_ERROR "PENSIGHT_SANITIZE and PENSIGHT_TSAN exclude each other; pick one")
endif()

function(pensight_set_sanitizers target)
  if(PENSIGHT_SANITIZE)
    target_compile_options(${target} PRIVATE
      $<$<COMPILE_LANGUAGE:CXX>:-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all>)
    target_link_options(${target} PUBLIC -fsanitize=address,undefined)
  endif()
  if(PENSIGHT_SANITIZE AND CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    set(ignorelist ${PROJECT_SOURCE_DIR}/cmake/sanitizer-ignorelist.txt)
    target_compile_options(${target} PRIVATE
      $<$<COMPILE_LANGUAGE:CXX>:-fsanitize-ignorelist=${ignorelist}>)
  endif()
  if(PENSIGHT_FUZZ)
    target_compile_options(${target} PRIVATE $<$<COMPILE_LANGUAGE:CXX>:-fsanitize=fuzzer-no-link>)
  endif()
  if(PENSIGHT_TSAN)
    target_compile_options(${target} PRIVATE
      $<$<COMPILE_LANGUAGE:CXX>:-fsanitize=thread -fno-omit-frame-pointer>)
    target_link_options(${target} PUBLIC -fsanitize=thread)
  endif()
endfunction()
