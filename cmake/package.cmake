# The install and the CMake package (docs/library.md): `cmake --install` puts the command, the
# libraries with their headers, the kernels' GLSL and the bundled scenes under the prefix, and
# find_package(rayspace CONFIG) gives the rayspace:: targets and rayspace_add_kernel_diff().
#
# The libraries are static archives, versioned by the package (rayspaceConfigVersion.cmake), not by a
# SOVERSION: the kernels' element functions are inline in the headers and must compile into the
# consumer under the same float rules (rayspace::fp_rules), so a consumer rebuilds against each
# release anyway, and 0.x promises no ABI.
if(BUILD_SHARED_LIBS)
  message(FATAL_ERROR "rayspace builds static libraries only (cmake/package.cmake says why); configure without BUILD_SHARED_LIBS")
endif()
include(CMakePackageConfigHelpers)

set(RAYSPACE_EXPORTED rayspace_fp_rules rayspace_platform rayspace_contract rayspace_scene rayspace_core rayspace_emu rayspace_exact
                      rayspace_refs rayspace_verify rayspace_sim rayspace_accuracy rayspace_mutate rayspace_reproduce rayspace_plot rayspace_data
                      rayspace_frame rayspace_commands)
if(RAYSPACE_HAVE_VULKAN)
  list(APPEND RAYSPACE_EXPORTED rayspace_gpu rayspace_diff rayspace_export rayspace_api)
endif()
list(APPEND RAYSPACE_EXPORTED rayspace)
foreach(t ${RAYSPACE_EXPORTED})
  string(REGEX REPLACE "^rayspace_" "" name ${t})
  set_target_properties(${t} PROPERTIES EXPORT_NAME ${name})
endforeach()
install(TARGETS ${RAYSPACE_EXPORTED} EXPORT rayspaceTargets
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT bin
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
# OpenImageIO's module, loaded at run time from lib/rayspace/ beside bin/ (core/CMakeLists.txt).
install(TARGETS rayspace_image_oiio LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/rayspace COMPONENT bin)

# What the binaries read at run time (rayspace/install_paths.h): the kernels and their includes (a
# user kernel includes them; `mutate` rewrites the kernels), the bundled scenes, the survivors list.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/gpu/shaders/ DESTINATION ${CMAKE_INSTALL_DATADIR}/rayspace/shaders COMPONENT bin)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/scenes/ DESTINATION ${CMAKE_INSTALL_DATADIR}/rayspace/scenes COMPONENT bin
        FILES_MATCHING PATTERN "*.json")
install(FILES ${PROJECT_SOURCE_DIR}/docs/mutation-survivors.json DESTINATION ${CMAKE_INSTALL_DATADIR}/rayspace COMPONENT bin)

set(RAYSPACE_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/rayspace)
install(EXPORT rayspaceTargets NAMESPACE rayspace:: DESTINATION ${RAYSPACE_CMAKE_DIR} COMPONENT dev)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/rayspaceConfig.cmake.in ${PROJECT_BINARY_DIR}/rayspaceConfig.cmake
                              INSTALL_DESTINATION ${RAYSPACE_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/rayspaceConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/rayspaceConfig.cmake ${PROJECT_BINARY_DIR}/rayspaceConfigVersion.cmake
              ${PROJECT_SOURCE_DIR}/cmake/RayspaceKernelDiff.cmake
        DESTINATION ${RAYSPACE_CMAKE_DIR} COMPONENT dev)

# Debian packages (`cpack -G DEB` in the build folder, docs/library.md): `rayspace` (the command, the
# image module, the kernels' GLSL and the scenes) and `rayspace-dev` (libraries, headers, the CMake
# package). Shared-library dependencies are computed (dpkg-shlibdeps); the programs rayspace runs and
# the -dev packages find_package(rayspace) looks for are named here.
set(CPACK_PACKAGE_NAME rayspace)
set(CPACK_PACKAGE_VENDOR "rayspace")
set(CPACK_PACKAGE_CONTACT "rayspace developers <rayspace@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Emulator and verifier of GPU secondary-ray tracing with ray-space hierarchies")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_GENERATOR DEB)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL bin dev)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_BIN_PACKAGE_NAME rayspace)
set(CPACK_DEBIAN_DEV_PACKAGE_NAME rayspace-dev)
set(CPACK_DEBIAN_BIN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_DEV_PACKAGE_SECTION libdevel)
# glslc compiles a user's .comp kernel; spirv-opt and spirv-dis (spirv-tools) run in `mutate`.
set(CPACK_DEBIAN_BIN_PACKAGE_DEPENDS "glslc, spirv-tools")
# lavapipe (the Vulkan device where no GPU is), the validation layer (--validate), gnuplot (plots).
set(CPACK_DEBIAN_BIN_PACKAGE_RECOMMENDS "mesa-vulkan-drivers, vulkan-validationlayers, gnuplot-nox")
set(CPACK_DEBIAN_DEV_PACKAGE_DEPENDS
    "rayspace (= ${PROJECT_VERSION}), cmake, pkg-config, libembree-dev, libcgal-dev, libgmp-dev, libmpfr-dev, libglm-dev, nlohmann-json3-dev, libcli11-dev, libfmt-dev, libtinyobjloader-dev, libxxhash-dev, zlib1g-dev, libpng-dev, libssl-dev, libvulkan-dev, libspirv-cross-c-shared-dev, spirv-tools")
include(CPack)
