# cmake -DINPUT=default.yaml -DOUTPUT=embedded_default.cpp -P embed.cmake
# Writes the YAML file into a C++ raw string so the binary carries its default config.
file(READ ${INPUT} text)
file(WRITE ${OUTPUT} "// Generated from ${INPUT} at build time. Do not edit.\n"
  "namespace flipper::kernel::detail {\n"
  "extern const char* const kEmbeddedDefaultConfig;\n"
  "const char* const kEmbeddedDefaultConfig = R\"flipper_yaml(${text})flipper_yaml\";\n"
  "}  // namespace flipper::kernel::detail\n")
