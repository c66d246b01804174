// The unit of flipper_test_pch (tests/CMakeLists.txt): the target that compiles the precompiled
// header every test unit reuses. Nothing runs it.
