# Warnings for our own targets; -Werror where PENSIGHT_WERROR is on (CI). The sanitizer flags
# (cmake/PensightSanitizers.cmake) ride along, as every target of ours is set up here.
function(pensight_set_warnings target)
  target_compile_options(${target} PRIVATE
    $<$<COMPILE_LANGUAGE:CXX>:-Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion
      -Wno-missing-field-initializers>
    $<$<AND:$<COMPILE_LANGUAGE:CXX>,$<BOOL:${PENSIGHT_WERROR}>>:-Werror>
    # GCC's subobject-linkage check exempts only types of the main file; in a unity batch every
    # file is an included one, so a class holding its own file's anonymous-namespace type (our
    # Impl pattern) would warn.
    $<$<AND:$<COMPILE_LANGUAGE:CXX>,$<CXX_COMPILER_ID:GNU>,$<BOOL:${PENSIGHT_UNITY_BUILD}>>:-Wno-subobject-linkage>
    $<$<COMPILE_LANGUAGE:CUDA>:-Xcompiler=-Wall,-Wextra>
    $<$<AND:$<COMPILE_LANGUAGE:CUDA>,$<BOOL:${PENSIGHT_WERROR}>>:-Werror=all-warnings>)
  pensight_set_sanitizers(${target})
endfunction()
