# Warnings for our own targets; -Werror where PENSIGHT_WERROR is on (CI). The sanitizer flags
# (cmake/PensightSanitizers.cmake) ride along, as every target of ours is set up here.
function(pensight_set_warnings target)
  target_compile_options(${target} PRIVATE
    $<$<COMPILE_LANGUAGE:CXX>:-Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion
      -Wno-missing-field-initializers>
    $<$<AND:$<COMPILE_LANGUAGE:CXX>,$<BOOL:${PENSIGHT_WERROR}>>:-Werror>
    $<$<COMPILE_LANGUAGE:CUDA>:-Xcompiler=-Wall,-Wextra>
    $<$<AND:$<COMPILE_LANGUAGE:CUDA>,$<BOOL:${PENSIGHT_WERROR}>>:-Werror=all-warnings>)
  pensight_set_sanitizers(${target})
endfunction()
