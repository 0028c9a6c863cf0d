# Sanitizer builds of our own targets (scripts/test.sh --sanitize and --tsan). ThreadSanitizer
# cannot share a process with AddressSanitizer, so the two options exclude each other.
option(PENSIGHT_SANITIZE "Build with AddressSanitizer and UndefinedBehaviorSanitizer" OFF)
option(PENSIGHT_TSAN "Build with ThreadSanitizer" OFF)
if(PENSIGHT_SANITIZE AND PENSIGHT_TSAN)
  message(FATAL_ERROR "PENSIGHT_SANITIZE and PENSIGHT_TSAN exclude each other; pick one")
endif()

function(pensight_set_sanitizers target)
  if(PENSIGHT_SANITIZE)
    target_compile_options(${target} PRIVATE
      $<$<COMPILE_LANGUAGE:CXX>:-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all>)
    target_link_options(${target} PUBLIC -fsanitize=address,undefined)
  endif()
  if(PENSIGHT_TSAN)
    target_compile_options(${target} PRIVATE
      $<$<COMPILE_LANGUAGE:CXX>:-fsanitize=thread -fno-omit-frame-pointer>)
    target_link_options(${target} PUBLIC -fsanitize=thread)
  endif()
endfunction()
