0 BEGIN PGM H29 MM
1 ; M120 LA3: a slot 6 mm wide, the tool 10 mm: the TNC leaves out what it cannot machine
2 TOOL DEF 1 L+50 R+5
3 TOOL CALL 1 Z S3000
4 L X-10 Y+10 R0 FMAX
5 L X+0 Y+0 RL F400 M120 LA3
6 L X+20
7 L Y-20
8 L X+26
9 L Y+0
10 L X+50
11 L X+60 Y+10 R0
12 END PGM H29 MM
