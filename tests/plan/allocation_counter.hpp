#pragma once
// The number of operator new calls so far in this test program (allocation_counter.cpp replaces
// the global operator new to count them), so a test can prove that code does not allocate.
namespace starnav::test {
long long allocation_count();
}
