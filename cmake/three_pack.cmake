# cmake -DSOURCE=integrations/three -DSTAGE=DIR -DTGZ=FILE -DCLI=microshadow -DNPM=npm -DNPM_CACHE=DIR -P three_pack.cmake
# (cmake/three_package.cmake): DIR = a fresh copy of SOURCE's package.json and src/*.js with src/generated/ from
# `CLI view --three-module`, then `npm pack DIR` into TGZ's folder. The source tree is not written.
file(REMOVE_RECURSE ${STAGE})
file(MAKE_DIRECTORY ${STAGE}/src)
file(COPY ${SOURCE}/package.json DESTINATION ${STAGE})
file(GLOB js ${SOURCE}/src/*.js)
file(COPY ${js} DESTINATION ${STAGE}/src)
execute_process(COMMAND ${CLI} view --three-module ${STAGE}/src/generated RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "microshadow view --three-module failed (${rc}): ${err}")
endif()
get_filename_component(dest ${TGZ} DIRECTORY)
file(REMOVE ${TGZ})
execute_process(COMMAND ${NPM} pack ${STAGE} --pack-destination ${dest} --cache ${NPM_CACHE} --ignore-scripts
                        --loglevel=error --no-audit --no-fund
                WORKING_DIRECTORY ${dest} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT EXISTS ${TGZ})
  message(FATAL_ERROR "npm pack ${STAGE} failed (${rc}) or wrote no ${TGZ}: ${out}${err}")
endif()
