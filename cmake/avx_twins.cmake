# The AVX twins' object (CMakeLists.txt, HK_AVX_TWIN_SOURCES; src/core/avx_twins.h):
#   cmake -DLINKER=ld -DNM=nm -DOBJCOPY=objcopy -DOBJECTS="a.o;b.o" -DOUT=twins.o -P avx_twins.cmake
# links the objects compiled with -mavx into one relocatable object, then renames every
# global symbol defined there NAME_avx, the calls among them with it. The names come
# from the objects themselves, so none can be forgotten: the twins never mix with the
# baseline's functions, and a twin that kept its name would clash at the link.
foreach(var LINKER NM OBJCOPY OBJECTS OUT)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "avx_twins.cmake: ${var} not given")
  endif()
endforeach()

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "avx_twins.cmake: ${ARGN} failed (${rc}): ${err}")
  endif()
  set(run_output "${out}" PARENT_SCOPE)
endfunction()

run(${LINKER} -r -o ${OUT}.joined.o ${OBJECTS})
run(${NM} --defined-only --extern-only --format=posix ${OUT}.joined.o)
string(REGEX MATCHALL "[^\n]+" lines "${run_output}")
set(renames "")
foreach(line IN LISTS lines)
  string(REGEX REPLACE " .*" "" name "${line}")
  # Functions only: a global variable would get a renamed copy, and the twins would keep
  # their own state beside the baseline's without a word (a file with one cannot be a twin).
  string(REGEX REPLACE "^[^ ]+ ([^ ]+).*" "\\1" type "${line}")
  if(NOT type STREQUAL "T")
    message(FATAL_ERROR "avx_twins.cmake: ${name} (nm type ${type}) is not a function: "
                        "a twin would duplicate its state; take its file out of HK_AVX_TWIN_SOURCES")
  endif()
  string(APPEND renames "${name} ${name}_avx\n")
endforeach()
if(renames STREQUAL "")
  message(FATAL_ERROR "avx_twins.cmake: no symbol defined in ${OBJECTS}")
endif()
file(WRITE ${OUT}.renames "${renames}")
run(${OBJCOPY} --redefine-syms=${OUT}.renames ${OUT}.joined.o ${OUT})
