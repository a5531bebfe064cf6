#!/bin/sh
# fake_test_listing.sh: stands in for both a Catch2 test program and ctest, so that ctest can check
# that check_test_count.cmake fails on the very faults it exists for (tests/CMakeLists.txt).
#   --list-test-names-only: lists four test cases, one with ';' and one with an unmatched ']';
#   -N (as ctest): the entries catch_discover_tests makes of them (split at ';', and the ']' one
#   merged with the case after it), plus one name that no program lists.
case "$1" in
  --list-test-names-only)
    printf '%s\n' 'split; in two' 'range (0, 1] merges' 'the next case' 'fine'
    exit 4 ;;
  -N)
    printf '%s\n' 'Test project /fake' \
      '  Test  #1: fake:split' \
      '  Test  #2: fake: in two' \
      '  Test  #3: fake:range (0, 1] merges;the next case' \
      '  Test  #4: fake:fine' \
      '  Test  #5: fake:never listed' \
      '' 'Total Tests: 5'
    exit 0 ;;
esac
exit 2
