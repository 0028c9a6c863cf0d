include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

# The installed headers keep the include paths the code uses ("pipeline/fft/net_detector.h"), under
# their own folder so they cannot clash with another package's runtime/ or pipeline/.
set(PENSIGHT_INSTALL_INCLUDEDIR ${CMAKE_INSTALL_INCLUDEDIR}/pensight)
set(PENSIGHT_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/pensight)

# pensight_add_layer(NAME NAMESPACE NS... [DEPENDS LAYER...]): the static library of the layer
# whose folder calls it, linking the layers below it (DEPENDS). NAMESPACE lists the namespaces its
# code opens (scripts/check-layers.py checks them). Its folder's headers are installed, *_detail.h
# (implementation-only) and internal/ folders excepted; the library is exported as pensight::NAME and linked by
# `pensight`.
function(pensight_add_layer name)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "" "NAMESPACE;DEPENDS")
  if(NOT arg_NAMESPACE)
    message(FATAL_ERROR "pensight_add_layer(${name}): NAMESPACE is missing (the namespaces of its code)")
  endif()
  add_library(${name} STATIC)
  add_library(pensight::${name} ALIAS ${name})
  target_include_directories(${name} PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>
                                            $<INSTALL_INTERFACE:${PENSIGHT_INSTALL_INCLUDEDIR}>)
  target_link_libraries(${name} PUBLIC ${arg_DEPENDS})
  pensight_set_warnings(${name})
  if(PENSIGHT_CUDA)
    set_target_properties(${name} PROPERTIES CUDA_SEPARABLE_COMPILATION OFF)
  endif()
  target_link_libraries(pensight INTERFACE ${name})
  set_property(GLOBAL APPEND PROPERTY PENSIGHT_LAYERS ${name})
  file(RELATIVE_PATH folder ${PROJECT_SOURCE_DIR} ${CMAKE_CURRENT_SOURCE_DIR})
  install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/
          DESTINATION ${PENSIGHT_INSTALL_INCLUDEDIR}/${folder}
          FILES_MATCHING PATTERN "*.h" PATTERN "*_detail.h" EXCLUDE PATTERN "internal" EXCLUDE)
endfunction()

# `cmake --install BUILD --prefix P`: the layers' libraries and headers, and
# P/lib/cmake/pensight/pensightConfig.cmake for find_package(pensight).
function(pensight_install_package)
  get_property(layers GLOBAL PROPERTY PENSIGHT_LAYERS)
  install(TARGETS ${layers} pensight EXPORT pensightTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(EXPORT pensightTargets NAMESPACE pensight:: DESTINATION ${PENSIGHT_INSTALL_CMAKEDIR})
  configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/pensightConfig.cmake.in
                                ${PROJECT_BINARY_DIR}/pensightConfig.cmake
                                INSTALL_DESTINATION ${PENSIGHT_INSTALL_CMAKEDIR})
  # 0.x: a minor release may break the API, so only the same minor version satisfies a request.
  write_basic_package_version_file(${PROJECT_BINARY_DIR}/pensightConfigVersion.cmake
                                   COMPATIBILITY SameMinorVersion)
  install(FILES ${PROJECT_BINARY_DIR}/pensightConfig.cmake
                ${PROJECT_BINARY_DIR}/pensightConfigVersion.cmake
          DESTINATION ${PENSIGHT_INSTALL_CMAKEDIR})
endfunction()

# pensight_forbid_links(TARGET PATTERN...): stops the configure when anything TARGET links, directly
# or through its dependencies, matches a regex PATTERN. Keeps the layers that must run on a
# vehicle computer without a GPU stack (control, MAVLink, the vehicle model) free of it.
function(pensight_forbid_links target)
  set(todo ${target})
  set(seen "")
  while(todo)
    list(POP_FRONT todo t)
    if(t IN_LIST seen OR NOT TARGET ${t})
      continue()
    endif()
    list(APPEND seen ${t})
    get_target_property(links ${t} LINK_LIBRARIES)
    get_target_property(interface_links ${t} INTERFACE_LINK_LIBRARIES)
    foreach(link IN LISTS links interface_links)
      string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" link "${link}")
      foreach(pattern ${ARGN})
        if(link MATCHES "${pattern}")
          message(FATAL_ERROR "${target} links ${link} (through ${t}); it may not link anything "
                              "matching '${pattern}': move the code it needs down to core/")
        endif()
      endforeach()
      if(link AND NOT link MATCHES "-NOTFOUND$")
        list(APPEND todo ${link})
      endif()
    endforeach()
  endwhile()
endfunction()
