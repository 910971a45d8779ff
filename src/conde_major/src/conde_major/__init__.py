"""Major Alvega (Ackermann robot of the original Conde simulator): its Ackermann controller."""
