# `cmake --install` puts the CLI in bin/ and the C++ library a user links (util, models, integrate,
# tables) with its headers in include/ganzfeld/ and lib/; `find_package(ganzfeld)` then gives
# the targets ganzfeld::models, ganzfeld::integrate, ganzfeld::tables (tests/consumer/ builds one).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)
set(GANZFELD_INSTALLED_MODULES util models integrate tables)
foreach(module ${GANZFELD_INSTALLED_MODULES})
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${module} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/ganzfeld
          FILES_MATCHING PATTERN "*.h")
  list(APPEND GANZFELD_INSTALLED_TARGETS ganzfeld_${module})
endforeach()
install(TARGETS ${GANZFELD_INSTALLED_TARGETS} EXPORT ganzfeldTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(EXPORT ganzfeldTargets NAMESPACE ganzfeld:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/ganzfeld)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/ganzfeldConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/ganzfeldConfig.cmake
                              INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/ganzfeld)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/ganzfeldConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/ganzfeldConfig.cmake ${PROJECT_BINARY_DIR}/ganzfeldConfigVersion.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/ganzfeld)
