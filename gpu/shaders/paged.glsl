// Arrays that may outgrow one binding (maxStorageBufferRange) are bound as kBufferPages (4)
// consecutive bindings, "pages", of `page` elements each: element i is element i % page of page
// i / page. The host fills the pages in order and binds one zeroed element for an unused page
// (gpu/src/kernels.cpp, MakePaged). Shader storage buffer arrays would be tidier, but indexing them
// with a value that differs between invocations needs shaderStorageBufferArrayNonUniformIndexing,
// which lavapipe lacks; separate bindings selected by a branch need no feature.
//
// PAGED_BUFFER(qualifier, NAME, T, B) declares bindings B .. B + 3. Accessors, each taking the
// element index and the page size in elements:
//   PAGED_LOAD(NAME, T)       T    LoadNAME(i, page)
//   PAGED_STORE(NAME, T)      void StoreNAME(i, page, x)
//   PAGED_ATOMIC(OP, NAME, T) void OPNAME(i, page, x)  (OP: atomicMin, atomicAdd, atomicExchange, ...)
#define PAGED_BUFFER(QUAL, NAME, T, B)                                   \
  layout(std430, binding = B) QUAL buffer NAME##_b0 { T v[]; } NAME##_p0;     \
  layout(std430, binding = B + 1) QUAL buffer NAME##_b1 { T v[]; } NAME##_p1; \
  layout(std430, binding = B + 2) QUAL buffer NAME##_b2 { T v[]; } NAME##_p2; \
  layout(std430, binding = B + 3) QUAL buffer NAME##_b3 { T v[]; } NAME##_p3;

#ifndef PAGED_FAULT
#define PAGED_FAULT 0u  // a kernel defines it to plant "every load reads the first page" as that fault
#endif

#define PAGED_LOAD(NAME, T)                         \
  T Load##NAME(uint i, uint page) {                 \
    const uint p = (PAGED_FAULT != 0u && kFault == PAGED_FAULT) ? 0u : i / page, j = i - (i / page) * page; \
    if (p == 0u) return NAME##_p0.v[j];             \
    if (p == 1u) return NAME##_p1.v[j];             \
    if (p == 2u) return NAME##_p2.v[j];             \
    return NAME##_p3.v[j];                          \
  }

#define PAGED_STORE(NAME, T)                        \
  void Store##NAME(uint i, uint page, T x) {        \
    const uint p = i / page, j = i - p * page;      \
    if (p == 0u) NAME##_p0.v[j] = x;                \
    else if (p == 1u) NAME##_p1.v[j] = x;           \
    else if (p == 2u) NAME##_p2.v[j] = x;           \
    else NAME##_p3.v[j] = x;                        \
  }

#define PAGED_ATOMIC(OP, NAME, T)                   \
  void OP##NAME(uint i, uint page, T x) {           \
    const uint p = i / page, j = i - p * page;      \
    if (p == 0u) OP(NAME##_p0.v[j], x);             \
    else if (p == 1u) OP(NAME##_p1.v[j], x);        \
    else if (p == 2u) OP(NAME##_p2.v[j], x);        \
    else OP(NAME##_p3.v[j], x);                     \
  }
