# `cmake --install BUILD --prefix PREFIX`: the libraries, their headers (PREFIX/include/penumbra,
# included as in the source tree) and the CMake package Penumbra (PenumbraConfig.cmake, its version
# file and the exported targets Penumbra::raster, ::stochastic, ::shadows, ::engine_core,
# ::engine). tests/package builds a consumer against such a prefix. docs/library.md says what is
# stable.
include(CMakePackageConfigHelpers)

set(PENUMBRA_LIBRARIES penumbra_raster penumbra_stochastic penumbra_shadows penumbra_engine_core penumbra_engine)
foreach(lib IN LISTS PENUMBRA_LIBRARIES)
  string(REPLACE "penumbra_" "" short ${lib})
  set_target_properties(${lib} PROPERTIES EXPORT_NAME ${short})
endforeach()
# The option libraries travel with the targets: -ffp-contract=off and the GLM defines are part of
# the ABI (the headers' inline code must compute what the libraries compute).
set_target_properties(penumbra_options PROPERTIES EXPORT_NAME options)
set_target_properties(penumbra_warnings PROPERTIES EXPORT_NAME warnings)

install(TARGETS ${PENUMBRA_LIBRARIES} penumbra_options penumbra_warnings
        EXPORT PenumbraTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/penumbra)
foreach(dir raster stochastic shadows engine)
  install(DIRECTORY ${dir} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/penumbra FILES_MATCHING PATTERN "*.h")
endforeach()
# The image module (engine/image_module.h) where the engine looks for it.
install(TARGETS penumbra_image_oiio LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/penumbra)
install(FILES ${PROJECT_BINARY_DIR}/generated/engine/version.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/penumbra/engine)

set(PENUMBRA_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/Penumbra)
install(EXPORT PenumbraTargets NAMESPACE Penumbra:: DESTINATION ${PENUMBRA_CMAKE_DIR})
configure_package_config_file(cmake/PenumbraConfig.cmake.in ${PROJECT_BINARY_DIR}/PenumbraConfig.cmake
                              INSTALL_DESTINATION ${PENUMBRA_CMAKE_DIR})
# 0.x: a minor version may change the API, so only the same minor version is compatible.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/PenumbraConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/PenumbraConfig.cmake ${PROJECT_BINARY_DIR}/PenumbraConfigVersion.cmake
        DESTINATION ${PENUMBRA_CMAKE_DIR})
