// SPDX-License-Identifier: MIT
// om_dthex: closed triangle surface in, all-hexahedral mesh out.
#include <cstdio>
int main() { std::puts("om_dthex: not yet wired"); return 0; }
