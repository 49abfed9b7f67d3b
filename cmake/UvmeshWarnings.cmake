# Common compile flags for every uvmesh target: warnings, optional -Werror, sanitizers.
if(UVMESH_SANITIZE STREQUAL "ON")
  set(UVMESH_SANITIZE "address,undefined")
endif()

function(uvmesh_target_defaults tgt)
  target_compile_options(${tgt} PRIVATE -Wall -Wextra -Wpedantic -Wshadow=local)
  if(UVMESH_WERROR)
    target_compile_options(${tgt} PRIVATE -Werror)
  endif()
endfunction()

if(UVMESH_SANITIZE)
  # Applied globally so that every object, test and tool is instrumented alike.
  add_compile_options(-fsanitize=${UVMESH_SANITIZE} -fno-omit-frame-pointer -fno-sanitize-recover=all)
  add_link_options(-fsanitize=${UVMESH_SANITIZE})
endif()
