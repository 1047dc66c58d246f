/*
 * gltf_accessor.cpp: accessors read into plain arrays (gltf_context.h). tinygltf checks the JSON's
 * shape but not that an accessor's bytes lie inside its buffer view and buffer: every range is
 * checked here, in 64-bit arithmetic that cannot overflow, before a byte is read, and every read
 * is a memcpy (glTF's alignment rules are not trusted either). min and max are not read.
 */
#include <cmath>
#include <cstring>

#include "gltf_context.h"

namespace gltf {

namespace {

int component_count(int type)
{
    switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    case TINYGLTF_TYPE_MAT2: return 4;
    case TINYGLTF_TYPE_MAT3: return 9;
    case TINYGLTF_TYPE_MAT4: return 16;
    }
    return 0;
}

/* Bytes of one component; 0 for a type glTF does not allow in an accessor. */
size_t component_size(int type)
{
    switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    }
    return 0;
}

/* One component at p as a float: glTF 2.0's normalisation for integers (spec 3.11:
 * max(c / 127, -1) for bytes, c / 255 for unsigned bytes, and so on). */
float component(const unsigned char *p, int type, bool normalized)
{
    switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
        int8_t v;
        memcpy(&v, p, 1);
        return normalized ? std::fmax(v / 127.0f, -1.0f) : (float)v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? p[0] / 255.0f : (float)p[0];
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
        int16_t v;
        memcpy(&v, p, 2);
        return normalized ? std::fmax(v / 32767.0f, -1.0f) : (float)v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        uint16_t v;
        memcpy(&v, p, 2);
        return normalized ? v / 65535.0f : (float)v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
        uint32_t v;
        memcpy(&v, p, 4);
        return normalized ? (float)(v / 4294967295.0) : (float)v;
    }
    default: {
        float v;
        memcpy(&v, p, 4);
        return v;
    }
    }
}

/* Where `count` elements of element_bytes each, stride apart, start `offset` bytes into buffer
 * view `view`: a pointer to the first, after checking that the view lies in its buffer and the
 * elements in the view. stride 0 means the view's byteStride, else tightly packed. */
const unsigned char *locate(const Context &c, int view, uint64_t offset, uint64_t count,
                            uint64_t element_bytes, uint64_t *stride, const std::string &where)
{
    const tinygltf::Model &g = c.gltf;
    if (view < 0 || (size_t)view >= g.bufferViews.size())
        c.fail(where, "bufferView " + std::to_string(view) + " is not one of the file's " +
                          std::to_string(g.bufferViews.size()));
    const tinygltf::BufferView &bv = g.bufferViews[(size_t)view];
    std::string view_name = item("bufferViews", (size_t)view);
    if (bv.buffer < 0 || (size_t)bv.buffer >= g.buffers.size())
        c.fail(view_name, "buffer " + std::to_string(bv.buffer) + " is not one of the file's " +
                              std::to_string(g.buffers.size()));
    const tinygltf::Buffer &buffer = g.buffers[(size_t)bv.buffer];
    uint64_t buffer_bytes = buffer.data.size();
    if (bv.byteOffset > buffer_bytes || bv.byteLength > buffer_bytes - bv.byteOffset)
        c.fail(view_name, "bytes " + std::to_string(bv.byteOffset) + " to " +
                              std::to_string((uint64_t)bv.byteOffset + bv.byteLength) +
                              " are past the end of buffer " + std::to_string(bv.buffer) + " (" +
                              std::to_string(buffer_bytes) + " bytes)");
    if (*stride == 0)
        *stride = bv.byteStride ? bv.byteStride : element_bytes;
    if (*stride < element_bytes)
        c.fail(where, "byteStride " + std::to_string(*stride) + " of " + view_name +
                          " is less than the " + std::to_string(element_bytes) +
                          " bytes of one element");
    if (count > 0) {
        /* offset + stride * (count - 1) + element_bytes <= byteLength, without overflow:
         * stride <= 252 + ... and count fits 2^32 (checked by the callers), so 64 bits hold it. */
        uint64_t span = *stride * (count - 1) + element_bytes;
        if (offset > bv.byteLength || span > bv.byteLength - offset)
            c.fail(where, std::to_string(count) + " elements of " + std::to_string(element_bytes) +
                              " bytes, " + std::to_string(*stride) + " apart from byte " +
                              std::to_string(offset) + ", run past the " +
                              std::to_string(bv.byteLength) + " bytes of " + view_name);
    }
    return buffer.data.data() + bv.byteOffset + offset;
}

/* The most elements an accessor may have: the model's arrays count in uint32s. */
const uint64_t MAX_ELEMENTS = UINT32_MAX;

const tinygltf::Accessor &checked_accessor(const Context &c, int accessor, const std::string &where)
{
    if (accessor < 0 || (size_t)accessor >= c.gltf.accessors.size())
        c.fail(where, "accessor " + std::to_string(accessor) + " is not one of the file's " +
                          std::to_string(c.gltf.accessors.size()));
    const tinygltf::Accessor &a = c.gltf.accessors[(size_t)accessor];
    if ((uint64_t)a.count > MAX_ELEMENTS)
        c.fail(item("accessors", (size_t)accessor),
               "count " + std::to_string(a.count) + " is more than vkrt reads (2^32 - 1)");
    return a;
}

} // namespace

size_t accessor_count(const Context &c, int accessor, const std::string &where)
{
    return checked_accessor(c, accessor, where).count;
}

std::vector<float> read_floats(Context &c, int accessor, int components, bool float_only,
                               bool finite, const std::string &where)
{
    const tinygltf::Accessor &a = checked_accessor(c, accessor, where);
    std::string name = where + ": " + item("accessors", (size_t)accessor);
    if (component_count(a.type) != components)
        c.fail(name, "has " + std::to_string(component_count(a.type)) +
                         " components per element where " + std::to_string(components) +
                         " are needed");
    size_t size = component_size(a.componentType);
    if (size == 0 || (float_only && a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT))
        c.fail(name, "componentType " + std::to_string(a.componentType) +
                         (float_only ? " where FLOAT (5126) is needed" : " is not one glTF allows"));
    uint64_t element = (uint64_t)size * (uint64_t)components;
    std::vector<float> out((size_t)a.count * (size_t)components, 0.0f);
    if (a.bufferView >= 0) {
        uint64_t stride = 0;
        const unsigned char *p =
            locate(c, a.bufferView, a.byteOffset, a.count, element, &stride, name);
        for (size_t i = 0; i < a.count; ++i, p += stride)
            for (int k = 0; k < components; ++k)
                out[i * (size_t)components + (size_t)k] =
                    component(p + (size_t)k * size, a.componentType, a.normalized);
    }
    if (a.sparse.isSparse) {
        std::string sparse = name + ".sparse";
        if (a.sparse.count < 0 || (uint64_t)a.sparse.count > a.count)
            c.fail(sparse, "count " + std::to_string(a.sparse.count) + " is more than the " +
                               std::to_string(a.count) + " elements");
        if (a.sparse.indices.byteOffset < 0 || a.sparse.values.byteOffset < 0)
            c.fail(sparse, "a negative byteOffset");
        int index_type = a.sparse.indices.componentType;
        size_t index_size = component_size(index_type);
        if (index_size == 0 || index_type == TINYGLTF_COMPONENT_TYPE_BYTE ||
            index_type == TINYGLTF_COMPONENT_TYPE_SHORT || index_type == TINYGLTF_COMPONENT_TYPE_FLOAT)
            c.fail(sparse, "indices of componentType " + std::to_string(index_type));
        uint64_t count = (uint64_t)a.sparse.count, index_stride = index_size, value_stride = element;
        const unsigned char *indices = locate(c, a.sparse.indices.bufferView,
                                              (uint64_t)a.sparse.indices.byteOffset, count,
                                              index_size, &index_stride, sparse + ".indices");
        const unsigned char *values = locate(c, a.sparse.values.bufferView,
                                             (uint64_t)a.sparse.values.byteOffset, count, element,
                                             &value_stride, sparse + ".values");
        for (uint64_t i = 0; i < count; ++i) {
            uint64_t at = (uint64_t)component(indices + i * index_size, index_type, false);
            if (at >= a.count)
                c.fail(sparse, "index " + std::to_string(at) + " is past the " +
                                   std::to_string(a.count) + " elements");
            for (int k = 0; k < components; ++k)
                out[(size_t)at * (size_t)components + (size_t)k] =
                    component(values + i * element + (size_t)k * size, a.componentType,
                              a.normalized);
        }
    }
    if (finite)
        for (size_t i = 0; i < out.size(); ++i)
            if (!std::isfinite(out[i]))
                c.fail(name, "element " + std::to_string(i / (size_t)components) +
                                 " is not a finite number");
    return out;
}

std::vector<uint32_t> read_indices(Context &c, int accessor, size_t vertex_count,
                                   const std::string &where)
{
    const tinygltf::Accessor &a = checked_accessor(c, accessor, where);
    std::string name = where + ": indices " + item("accessors", (size_t)accessor);
    if (a.type != TINYGLTF_TYPE_SCALAR ||
        (a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
         a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
         a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
        c.fail(name, "must be SCALAR of unsigned byte, short or int");
    if (a.sparse.isSparse || a.bufferView < 0)
        c.fail(name, "sparse or without a bufferView: vkrt reads indices only from a buffer view");
    size_t size = component_size(a.componentType);
    uint64_t stride = 0;
    const unsigned char *p = locate(c, a.bufferView, a.byteOffset, a.count, size, &stride, name);
    std::vector<uint32_t> out(a.count);
    for (size_t i = 0; i < a.count; ++i, p += stride) {
        uint32_t v = 0;
        if (size == 1)
            v = p[0];
        else if (size == 2) {
            uint16_t s;
            memcpy(&s, p, 2);
            v = s;
        } else
            memcpy(&v, p, 4);
        if (v >= vertex_count)
            c.fail(name, "index " + std::to_string(i) + " is " + std::to_string(v) +
                             ", past the " + std::to_string(vertex_count) + " vertices of POSITION");
        out[i] = v;
    }
    return out;
}

} // namespace gltf
