# The docs stay readable: README.md is a front door under 150 lines, docs/performance.md under 300,
# and docs/README.md indexes every page of docs/, so that none is found only by accident.
#   cmake -DSRC=<source dir> -P docs_caps.cmake
cmake_minimum_required(VERSION 3.19)

# Lines as wc -l counts them: file(STRINGS) would skip the empty ones.
function(line_count path out)
  file(READ "${path}" text)
  string(REGEX MATCHALL "\n" newlines "${text}")
  list(LENGTH newlines n)
  set(${out} ${n} PARENT_SCOPE)
endfunction()

set(failures "")
foreach(cap "README.md:150" "docs/performance.md:300")
  string(REPLACE ":" ";" cap "${cap}")
  list(GET cap 0 doc)
  list(GET cap 1 limit)
  line_count("${SRC}/${doc}" n)
  if(NOT n LESS limit)
    set(failures "${failures}\n${doc}: ${n} lines; it must stay under ${limit} (move detail to the doc it belongs to)")
  endif()
endforeach()

file(READ "${SRC}/docs/README.md" index)
file(GLOB pages RELATIVE "${SRC}/docs" "${SRC}/docs/*.md")
list(REMOVE_ITEM pages README.md)  # the index itself
list(SORT pages)
foreach(page ${pages})
  string(FIND "${index}" "](${page})" at)
  if(at EQUAL -1)
    set(failures "${failures}\ndocs/README.md: no link to docs/${page} ('](${page})'); add one line for it to the index")
  endif()
endforeach()

if(failures)
  message(FATAL_ERROR "${failures}")
endif()
list(LENGTH pages n)
message(STATUS "docs caps: README.md and docs/performance.md under their caps, docs/README.md indexes all ${n} pages")
