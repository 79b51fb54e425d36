# Turns a text file into a C++ header holding its bytes and a terminating zero.
# cmake -DIN=x.c -DOUT=x.h -DNAME=kX -P embed_text.cmake
file(READ "${IN}" hex HEX)
string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," body "${hex}")
file(WRITE "${OUT}" "// Generated from ${IN}; do not edit.\n#pragma once\ninline constexpr char ${NAME}[] = {\n${body}0};\n")
