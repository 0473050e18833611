# cmake -DDEPFILE=F -DTARGET=T -P DepfileTarget.cmake: names T as the target of glslang's depfile
# F, which names the file glslang wrote (the raw module), so that the build tool, which looks for
# the custom command's output there, sees the shader's includes.
file(READ ${DEPFILE} rules)
string(FIND "${rules}" ": " colon)
if(colon LESS 0)
  message(FATAL_ERROR "${DEPFILE}: no target in glslang's depfile")
endif()
string(SUBSTRING "${rules}" ${colon} -1 prerequisites)
file(WRITE ${DEPFILE} "${TARGET}${prerequisites}")
