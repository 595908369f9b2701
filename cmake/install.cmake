# install.cmake — what `cmake --install build --prefix P` puts under P:
#   lib/libbvox.so.0 (+ the libbvox.so link) or lib/libbvox.a, include/bvox.h,
#   include/bvox/*.h (version.h generated), lib/pkgconfig/bvox.pc,
#   lib/cmake/bvox/ (find_package(bvox) -> bvox::bvox), bin/bvox,
#   share/man/man1/*.1 and share/bash-completion/completions/bvox.
include(CMakePackageConfigHelpers)

set(BVOX_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/bvox)

install(TARGETS bvox EXPORT bvoxTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} NAMELINK_COMPONENT Development
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS bvox_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(FILES ${CMAKE_CURRENT_SOURCE_DIR}/include/bvox.h
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/bvox/
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/bvox FILES_MATCHING PATTERN "*.h")
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/include/bvox/version.h
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/bvox)

# CMake package. A static libbvox carries its dependencies as link-only
# requirements, so the config then finds them again (a shared one hides them).
install(EXPORT bvoxTargets NAMESPACE bvox:: DESTINATION ${BVOX_CMAKE_DIR})
if(BVOX_SHARED)
  set(BVOX_FIND_DEPENDENCIES "")
else()
  set(BVOX_FIND_DEPENDENCIES "find_dependency(ZLIB)\nfind_dependency(PNG)\nfind_dependency(TIFF)\nfind_dependency(GIF)\nfind_dependency(Threads)")
endif()
configure_package_config_file(${CMAKE_CURRENT_SOURCE_DIR}/cmake/bvoxConfig.cmake.in
                              ${CMAKE_CURRENT_BINARY_DIR}/bvoxConfig.cmake
                              INSTALL_DESTINATION ${BVOX_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/bvoxConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMajorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/bvoxConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/bvoxConfigVersion.cmake
        DESTINATION ${BVOX_CMAKE_DIR})

# pkg-config. A static library lists its dependencies for `--static`.
if(BVOX_SHARED)
  set(BVOX_PC_LIBS_PRIVATE "")
  set(BVOX_PC_REQUIRES_PRIVATE "")
else()
  set(BVOX_PC_LIBS_PRIVATE "-lgif -lpthread -lm")
  set(BVOX_PC_REQUIRES_PRIVATE "zlib libpng libtiff-4 blosc")
endif()
# Relocatable: paths relative to the .pc file itself, so that
# `cmake --install build --prefix P` (a prefix chosen at install time) works.
string(REPLACE "/" ";" _bvox_libdir_parts "${CMAKE_INSTALL_LIBDIR}/pkgconfig")
set(BVOX_PC_PREFIX "\${pcfiledir}")
foreach(_part IN LISTS _bvox_libdir_parts)
  string(APPEND BVOX_PC_PREFIX "/..")
endforeach()
configure_file(${CMAKE_CURRENT_SOURCE_DIR}/cmake/bvox.pc.in ${CMAKE_CURRENT_BINARY_DIR}/bvox.pc @ONLY)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/bvox.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

# Manual pages and bash completion, generated at build time by the command
# itself from its command tables (cmake/gen_docs.cmake).
# HOOK (issue 15 / branch cli-tables): `bvox help --man [CMD]` and
# `bvox help --bash-completion` come with the table-driven CLI. Until that
# lands, gen_docs.cmake finds the command lacks them, says so and generates
# nothing; the install rules below are OPTIONAL so installing still works.
set(BVOX_DOCS_DIR ${CMAKE_CURRENT_BINARY_DIR}/docs-gen)
add_custom_command(OUTPUT ${BVOX_DOCS_DIR}/stamp
                   COMMAND ${CMAKE_COMMAND} -DBVOX=$<TARGET_FILE:bvox_cli> -DOUT=${BVOX_DOCS_DIR}
                           -P ${CMAKE_CURRENT_SOURCE_DIR}/cmake/gen_docs.cmake
                   DEPENDS bvox_cli ${CMAKE_CURRENT_SOURCE_DIR}/cmake/gen_docs.cmake
                   COMMENT "Generating bvox manual pages and bash completion")
add_custom_target(bvox_docs ALL DEPENDS ${BVOX_DOCS_DIR}/stamp)
install(DIRECTORY ${BVOX_DOCS_DIR}/man1 DESTINATION ${CMAKE_INSTALL_MANDIR} OPTIONAL)
install(FILES ${BVOX_DOCS_DIR}/bvox.bash DESTINATION ${CMAKE_INSTALL_DATADIR}/bash-completion/completions
        RENAME bvox OPTIONAL)
