# s3m_add_module(<name> SOURCES ... DEPS ...)
# One static library target `s3m_<name>` (alias s3m::<name>) per folder under src/s3m/.
# Public include root is src/, so code includes "s3m/<module>/<header>.hpp".
function(s3m_add_module name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(s3m_${name} STATIC ${ARG_SOURCES})
  add_library(s3m::${name} ALIAS s3m_${name})
  target_include_directories(s3m_${name} PUBLIC ${PROJECT_SOURCE_DIR}/src)
  target_link_libraries(s3m_${name} PUBLIC ${ARG_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  target_compile_definitions(s3m_${name} PRIVATE S3M_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
endfunction()
