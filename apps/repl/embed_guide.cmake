# cmake -DINPUT=docs/language.md -DOUTPUT=language_guide.cpp -P embed_guide.cmake
# Writes the language guide into a C++ raw string: the repl's :examples come from it.
file(READ ${INPUT} text)
file(WRITE ${OUTPUT} "// Generated from ${INPUT} at build time. Do not edit.\n"
  "namespace flipper::repl::detail {\n"
  "extern const char* const kLanguageGuide;\n"
  "const char* const kLanguageGuide = R\"flipper_guide(${text})flipper_guide\";\n"
  "}  // namespace flipper::repl::detail\n")
