# Script mode: writes OUTPUT, a C header defining SYMBOL as the bytes of INPUT plus a NUL.
file(READ ${INPUT} hex HEX)
string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," bytes "${hex}")
string(REGEX REPLACE "(0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,)" "\\1\n"
       bytes "${bytes}")
file(WRITE ${OUTPUT} "/* generated from ${INPUT}; do not edit */\n"
     "static const char ${SYMBOL}[] = {\n${bytes}0x00};\n")
