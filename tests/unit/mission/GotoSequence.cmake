# Issue 11: goto through a sequence of goals (the taxi) on a fixed town map.
carril_add_test(goto_sequence_test SOURCES GotoSequenceTest.cpp
  LIBS carril_firmware carril_alloc_counter)
