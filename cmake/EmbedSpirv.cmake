set(TRAZADOR_DEPFILE_TARGET ${CMAKE_CURRENT_LIST_DIR}/DepfileTarget.cmake)

# embed_spirv(TARGET OUTDIR SHADER...): compiles each compute shader with glslangValidator into
# OUTDIR/<name>_spv.h (a `<name>_spv` uint32_t array); included .glsl files are tracked by depfile.
function(embed_spirv target outdir)
  set(headers)
  foreach(shader ${ARGN})
    get_filename_component(name ${shader} NAME_WE)
    set(header ${outdir}/${name}_spv.h)
    add_custom_command(
      OUTPUT ${header}
      COMMAND ${CMAKE_COMMAND} -E make_directory ${outdir}
      COMMAND ${GLSLANG_VALIDATOR} -V --target-env vulkan1.1 --quiet
              --depfile ${header}.d -o ${header}.raw.spv ${shader}
      COMMAND ${CMAKE_COMMAND} -DDEPFILE=${header}.d -DTARGET=${header}
              -P ${TRAZADOR_DEPFILE_TARGET}
      COMMAND spirv_exact ${header}.raw.spv ${header}.exact.spv
      COMMAND ${SPIRV_OPT} -Os --target-env=vulkan1.1 ${header}.exact.spv -o ${header}.spv
      COMMAND spirv_exact --header ${name}_spv ${header}.spv ${header}
      DEPENDS ${shader} spirv_exact
      DEPFILE ${header}.d
      COMMENT "Compiling ${name}.comp to SPIR-V")
    list(APPEND headers ${header})
  endforeach()
  add_custom_target(${target} DEPENDS ${headers})
endfunction()

# embed_spirv_variant(TARGET OUTDIR SHADER NAME DEFINE [ENV]): SHADER compiled with DEFINE set into
# OUTDIR/NAME_spv.h (a `NAME_spv` array): a second module of the same entry point, for the
# Vulkan version ENV (vulkan1.1 unless given).
function(embed_spirv_variant target outdir shader name define)
  set(env vulkan1.1)
  if(ARGC GREATER 5)
    set(env ${ARGV5})
  endif()
  set(header ${outdir}/${name}_spv.h)
  add_custom_command(
    OUTPUT ${header}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${outdir}
    COMMAND ${GLSLANG_VALIDATOR} -V --target-env ${env} --quiet -D${define}
            --depfile ${header}.d -o ${header}.raw.spv ${shader}
    COMMAND ${CMAKE_COMMAND} -DDEPFILE=${header}.d -DTARGET=${header} -P ${TRAZADOR_DEPFILE_TARGET}
    COMMAND spirv_exact ${header}.raw.spv ${header}.exact.spv
    COMMAND ${SPIRV_OPT} -Os --target-env=${env} ${header}.exact.spv -o ${header}.spv
    COMMAND spirv_exact --header ${name}_spv ${header}.spv ${header}
    DEPENDS ${shader} spirv_exact
    DEPFILE ${header}.d
    COMMENT "Compiling ${name} (${define}) to SPIR-V")
  add_custom_target(${target} DEPENDS ${header})
endfunction()
