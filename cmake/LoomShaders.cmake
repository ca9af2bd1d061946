# Shaders live in their own files under core/shaders/ and are compiled into the
# binary, so a bundled worker needs no data files next to it. Each shader keeps its
# file name: compile errors name the file and line.
#
# loom_embed_shaders(OUTPUT <cpp> FILES <shader files...>)
function(loom_embed_shaders)
  cmake_parse_arguments(ARG "" "OUTPUT" "FILES" ${ARGN})
  add_custom_command(
    OUTPUT ${ARG_OUTPUT}
    COMMAND ${CMAKE_COMMAND} -DOUTPUT=${ARG_OUTPUT} "-DFILES=${ARG_FILES}"
            -P ${PROJECT_SOURCE_DIR}/cmake/EmbedShaders.cmake
    DEPENDS ${ARG_FILES} ${PROJECT_SOURCE_DIR}/cmake/EmbedShaders.cmake
    COMMENT "Embedding shaders"
    VERBATIM)
endfunction()
