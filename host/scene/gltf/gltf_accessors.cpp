/* glTF import: warnings and the checked reading of accessors and buffer views. */
#include "gltf_importer.h"

namespace lvcl_gltf
{

void Importer::warn_once(const std::string &key, const char *fmt, ...)
{
    if (!warned.insert(key).second) return;
    va_list ap;
    va_start(ap, fmt);
    std::string msg = vformat(fmt, ap);
    va_end(ap);
    lvcl_warn("%s: %s", src, msg.c_str());
}

/* ---- accessors ---- */

/* The bytes of buffer view `view`, checked to lie inside its buffer. */
std::pair<const uint8_t *, size_t> Importer::view_bytes(int view, const char *what)
{
    if (view < 0 || (size_t)view >= m.bufferViews.size())
        fail(LVCL_ERR_PARSE, "%s: bufferView %d out of range (file has %zu)", what, view, m.bufferViews.size());
    const tinygltf::BufferView &bv = m.bufferViews[(size_t)view];
    if (bv.buffer < 0 || (size_t)bv.buffer >= m.buffers.size())
        fail(LVCL_ERR_PARSE, "bufferView %d: buffer %d out of range (file has %zu)", view, bv.buffer, m.buffers.size());
    const std::vector<unsigned char> &data = m.buffers[(size_t)bv.buffer].data;
    size_t end;
    if (add_overflows(bv.byteOffset, bv.byteLength, &end) || end > data.size())
        fail(LVCL_ERR_PARSE, "bufferView %d (offset %zu, length %zu) extends past the end of buffer %d (%zu bytes)",
             view, bv.byteOffset, bv.byteLength, bv.buffer, data.size());
    return {data.data() + bv.byteOffset, bv.byteLength};
}

AccessorSpan Importer::span(int accessor, const char *what)
{
    if (accessor < 0 || (size_t)accessor >= m.accessors.size())
        fail(LVCL_ERR_PARSE, "%s: accessor %d out of range (file has %zu)", what, accessor, m.accessors.size());
    const tinygltf::Accessor &a = m.accessors[(size_t)accessor];
    AccessorSpan s;
    s.comp_type = a.componentType;
    s.comps = component_count(a.type);
    s.count = a.count;
    s.normalized = a.normalized;
    size_t csize = component_size(a.componentType);
    if (csize == 0 || s.comps == 0)
        fail(LVCL_ERR_PARSE, "accessor %d: invalid componentType %d or type", accessor, a.componentType);
    s.elem_size = csize * (size_t)s.comps;
    if (a.count > (size_t)UINT32_MAX) fail(LVCL_ERR_PARSE, "accessor %d: count %zu is too large", accessor, a.count);
    if (a.bufferView == -1) return s; /* glTF: no bufferView means zeros (or sparse only) */

    auto bytes = view_bytes(a.bufferView, what);
    const tinygltf::BufferView &bv = m.bufferViews[(size_t)a.bufferView];
    s.stride = bv.byteStride ? bv.byteStride : s.elem_size;
    if (s.stride < s.elem_size)
        fail(LVCL_ERR_PARSE, "bufferView %d: byteStride %zu is smaller than accessor %d's element", a.bufferView,
             bv.byteStride, accessor);
    size_t need = 0;
    if (a.count > 0 &&
        (mul_overflows(a.count - 1, s.stride, &need) || add_overflows(need, s.elem_size, &need) ||
         add_overflows(need, a.byteOffset, &need) || need > bytes.second))
        fail(LVCL_ERR_PARSE,
             "accessor %d (offset %zu, count %zu, stride %zu) reads past the end of bufferView %d "
             "(%zu bytes)",
             accessor, a.byteOffset, a.count, s.stride, a.bufferView, bytes.second);
    s.base = bytes.first + a.byteOffset;
    return s;
}

/* Overwrites the elements a sparse accessor substitutes. */
void Importer::apply_sparse(int accessor, const AccessorSpan &s, std::vector<double> &out)
{
    const auto &sp = m.accessors[(size_t)accessor].sparse;
    if (sp.count < 0 || (size_t)sp.count > s.count)
        fail(LVCL_ERR_PARSE, "accessor %d: sparse count %d out of range", accessor, sp.count);
    if (!is_unsigned_int_type(sp.indices.componentType))
        fail(LVCL_ERR_PARSE, "accessor %d: sparse indices must be unsigned integers", accessor);
    if (sp.indices.byteOffset < 0 || sp.values.byteOffset < 0)
        fail(LVCL_ERR_PARSE, "accessor %d: negative sparse byteOffset", accessor);

    size_t n = (size_t)sp.count, isize = component_size(sp.indices.componentType);
    auto ib = view_bytes(sp.indices.bufferView, "sparse indices");
    auto vb = view_bytes(sp.values.bufferView, "sparse values");
    if ((size_t)sp.indices.byteOffset + n * isize > ib.second ||
        (size_t)sp.values.byteOffset + n * s.elem_size > vb.second)
        fail(LVCL_ERR_PARSE, "accessor %d: sparse data reads past the end of its bufferView", accessor);

    size_t csize = component_size(s.comp_type);
    for (size_t i = 0; i < n; i++) {
        double target = read_component(ib.first + sp.indices.byteOffset + i * isize, sp.indices.componentType, false);
        if (target >= (double)s.count)
            fail(LVCL_ERR_PARSE, "accessor %d: sparse index %.0f out of range (count %zu)", accessor, target, s.count);
        const uint8_t *src = vb.first + sp.values.byteOffset + i * s.elem_size;
        for (int c = 0; c < s.comps; c++)
            out[(size_t)target * (size_t)s.comps + (size_t)c] =
                read_component(src + (size_t)c * csize, s.comp_type, s.normalized);
    }
}

/* All components of an accessor, converted to doubles (sparse resolved). */
std::vector<double> Importer::read_accessor(int accessor, const char *what, AccessorSpan *info)
{
    AccessorSpan s = span(accessor, what);
    *info = s;
    std::vector<double> out(s.count * (size_t)s.comps, 0.0);
    size_t csize = component_size(s.comp_type);
    if (s.base)
        for (size_t i = 0; i < s.count; i++)
            for (int c = 0; c < s.comps; c++)
                out[i * (size_t)s.comps + (size_t)c] =
                    read_component(s.base + i * s.stride + (size_t)c * csize, s.comp_type, s.normalized);
    if (m.accessors[(size_t)accessor].sparse.isSparse) apply_sparse(accessor, s, out);
    return out;
}

} // namespace lvcl_gltf
