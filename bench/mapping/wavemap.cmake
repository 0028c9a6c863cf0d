# wavemap (ETH ASL) as the mapping benchmark's peer: only when PENSIGHT_WAVEMAP_DIR names a wavemap
# install prefix (built outside this repository; see bench/mapping/wavemap_peer.h for the version).
#
# wavemap's targets carry -march=native and EIGEN_INITIALIZE_MATRICES_BY_NAN, and its Eigen types
# are aligned for the widest vector unit. The adapter needs the same flags to use wavemap's headers,
# and nothing else may see them: it is a shared library that links wavemap PRIVATE and exports only
# pensight::bench::WavemapPeer (wavemap_peer.map), so no Eigen function compiled with AVX-512
# assumptions replaces the benchmark's own at link time.
# wavemap itself is found by the top-level CMakeLists.txt (its package config must run in the
# folder that found Boost).

add_library(pensight_wavemap_peer SHARED ${CMAKE_CURRENT_LIST_DIR}/wavemap_peer.cpp)
target_link_libraries(pensight_wavemap_peer PRIVATE wavemap::wavemap_core pensight)
target_link_options(pensight_wavemap_peer PRIVATE
                    -Wl,--version-script=${CMAKE_CURRENT_LIST_DIR}/wavemap_peer.map)
set_target_properties(pensight_wavemap_peer PROPERTIES LINK_DEPENDS
                                                       ${CMAKE_CURRENT_LIST_DIR}/wavemap_peer.map)
target_compile_definitions(pensight_wavemap_peer INTERFACE PENSIGHT_HAVE_WAVEMAP=1)
pensight_set_warnings(pensight_wavemap_peer)
