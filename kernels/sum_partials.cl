// Sum of n partial sums in a fixed order (host code: chunked_sum in reduction.hpp):
// 256 consecutive chunks, each summed in order, then the chunk sums in order.
// One work-group of REDUCE_GROUP (a divisor of 256) work-items, each summing every
// REDUCE_GROUP-th chunk.
kernel void sum_partials(global const acc* partial, uint n, global acc* total) {
    local acc chunks[256];
    const uint lid = (uint)get_local_id(0);
    const uint per = (n + 255u) / 256u;
    for (uint c = lid; c < 256u; c += REDUCE_GROUP) {
        const uint begin = min(n, c * per), end = min(n, begin + per);
        acc s = (acc)0;
        for (uint t = begin; t < end; ++t) s += partial[t];
        chunks[c] = s;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    if (lid == 0) {
        acc sum = (acc)0;
        for (int t = 0; t < 256; ++t) sum += chunks[t];
        total[0] = sum;
    }
}
