-- Prints what "cli: script arguments reach arg[]" expects, then fails: the test declared with this
-- script must fail (tests/CMakeLists.txt: wedge_output_test checks the exit status too).
print("args: " .. table.concat(arg, ",") .. ";")
error("failed after the expected output")
