# One library per layer, each compiled against a folder of its own that holds only the headers of
# the layers it may include (docs/DESIGN.md section 1): a wrong include fails the build with "No
# such file or directory". The folder is made of links to the headers of src/ (the compiler's
# messages name them by those links), made again when a header is added or removed.
function(trazador_layer_includes target)
  set(root ${CMAKE_BINARY_DIR}/layers/${target})
  file(REMOVE_RECURSE ${root})
  foreach(layer IN LISTS ARGN)
    file(GLOB headers CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/src/${layer}/*.h)
    file(MAKE_DIRECTORY ${root}/${layer})
    foreach(header IN LISTS headers)
      get_filename_component(name ${header} NAME)
      file(CREATE_LINK ${header} ${root}/${layer}/${name} SYMBOLIC)
    endforeach()
  endforeach()
  # The shared C/GLSL text (shaders/) every layer may read, then the layer's own folder.
  target_include_directories(${target} PRIVATE ${root} ${CMAKE_SOURCE_DIR}/shaders)
endfunction()
