# cmake -DSPV=in.spv -DOUT=out.cpp -DIDENT=name_comp -DNAME=name.comp -P EmbedSpirv.cmake
file(READ ${SPV} hex HEX)
string(LENGTH "${hex}" n)
math(EXPR bytes "${n} / 2")
math(EXPR rem "${bytes} % 4")
if(NOT rem EQUAL 0 OR bytes EQUAL 0)
  message(FATAL_ERROR "${SPV}: not a SPIR-V module (${bytes} bytes)")
endif()
math(EXPR words "${bytes} / 4")
# SPIR-V files are little-endian words: reverse the byte order of each 8-hex-digit group.
string(REGEX REPLACE "(..)(..)(..)(..)" "0x\\4\\3\\2\\1u," body "${hex}")
string(REGEX REPLACE "((0x........u,){8})" "\\1\n  " body "${body}")
file(WRITE ${OUT} "// Generated from ${NAME}: do not edit.
#include <cstdint>
#include <cstddef>
namespace rtsdf::gpu::detail {
extern const std::uint32_t ${IDENT}_words[] = {
  ${body}
};
extern const std::size_t ${IDENT}_count = ${words};
} // namespace rtsdf::gpu::detail
")
