include(CMakePackageConfigHelpers)
include(GNUInstallDirs)

install(TARGETS pcl_icf_registration pcl_icf_io pcl_icf_segmentation pcl_icf_localization pcl_icf_tracking pcl_icf_evaluation pcl_icf_pcl_deps
  EXPORT pcl_icfTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(EXPORT pcl_icfTargets NAMESPACE pcl_icf::
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/pcl_icf)
configure_package_config_file(cmake/pcl_icfConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/pcl_icfConfig.cmake
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/pcl_icf)
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/pcl_icfConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/pcl_icfConfig.cmake
  ${CMAKE_CURRENT_BINARY_DIR}/pcl_icfConfigVersion.cmake
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/pcl_icf)
