# s3m_add_module(<name> SOURCES ... DEPS ... [INTERNAL_HEADERS ...])
# One static library target `s3m_<name>` (alias s3m::<name>) per folder under src/s3m/.
# Public include root is src/, so code includes "s3m/<module>/<header>.hpp". `cmake --install`
# puts the library, its headers and its export entry (s3m::<name> for find_package(s3m)) under
# the prefix; see the top-level CMakeLists.txt. INTERNAL_HEADERS (paths relative to the module
# folder) are left out of the install: no installed header includes them (the install test checks).
include(GNUInstallDirs)

function(s3m_add_module name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS;PRIVATE_DEPS;INTERNAL_HEADERS" ${ARGN})
  add_library(s3m_${name} STATIC ${ARG_SOURCES})
  add_library(s3m::${name} ALIAS s3m_${name})
  set_target_properties(s3m_${name} PROPERTIES EXPORT_NAME ${name})
  target_include_directories(s3m_${name} PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/src>
                                                $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(s3m_${name} PUBLIC ${ARG_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  install(TARGETS s3m_${name} EXPORT s3mTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  set(excluded)
  foreach(h ${ARG_INTERNAL_HEADERS})  # PATTERN matches file names only: a path needs a REGEX
    string(REPLACE "." "\\." h_regex "${h}")
    list(APPEND excluded REGEX "/${h_regex}$" EXCLUDE)
  endforeach()
  install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/s3m/${name}
          FILES_MATCHING PATTERN "*.hpp" ${excluded})
endfunction()
