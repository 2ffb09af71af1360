0 BEGIN PGM H25_PART MM
1 ; called by h25_call_pgm.h: Q10 is the width, QL1 is this program's own
2 QL1 = -20
3 L X+QL1 Y+0 Z+2 R0 FMAX
4 L Z-5 F1000
5 L X+0 Y+0 RL F300
6 L Y+20
7 L X+Q10
8 L Y+0
9 L X+0
10 L X+QL1 Y-10 R0
11 L Z+2 FMAX
12 END PGM H25_PART MM
