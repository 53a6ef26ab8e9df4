# Writes OUT: a C++ file whose FUNCTION() (default page_html) returns the bytes of IN
# (build-time embedding).
if(NOT FUNCTION)
  set(FUNCTION page_html)
endif()
file(READ ${IN} hex HEX)
string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," bytes "${hex}")
file(WRITE ${OUT} "#include \"page_asset.hpp\"\nnamespace stereoball::view {\n"
  "static const unsigned char kPage[] = {${bytes}};\n"
  "std::string_view ${FUNCTION}() {\n"
  "  return {reinterpret_cast<const char*>(kPage), sizeof kPage};\n}\n}\n")
