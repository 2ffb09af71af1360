0 BEGIN PGM H20 MM
1 TOOL DEF 1 L+0 R+5
2 TOOL CALL 1 Z S3000
3 FN 0: Q1 = +60 ; width
4 FN 1: Q2 = +Q1 + -20 ; height 40
5 FN 2: Q3 = +Q1 - +Q2 ; arc radius 20
6 FN 3: Q4 = +Q3 * +0.5 ; chamfer 10
7 FN 4: Q5 = +Q1 DIV +4 ; 15
8 FN 5: Q6 = SQRT +64 ; rounding radius 8
9 FN 6: Q7 = SIN +30 ; 0.5
10 FN 7: Q8 = COS +60 ; 0.5
11 FN 8: Q9 = +30 LEN +40 ; 50
12 FN 13: Q10 = +10 ANG +10 ; 45 degrees
13 Q11 = Q9 * SIN Q10 + 2 ^ 2 - SQ 2 ; 35.3553
14 Q12 = (Q1 + Q2) / 2 * Q7 + ABS -3 + INT 2.7 + FRAC 1.25 + SGN -5 ; 29.25
15 Q13 = ATAN (Q7 / Q8) + ASIN Q7 + ACOS Q8 - 2 * TAN 45 * PI / PI ; feed 133
16 QL1 = Q4 * 2 ; depth 20
17 QR2 = QL1 / 4 ; clearance 5
18 L X-20 Y-20 Z+QR2 R0 FMAX
19 L Z-QL1 F1000
20 L X+0 Y+0 RL F300
21 L Y+Q2
22 RND R Q6
23 L X+Q1 FQ13
24 CR X+Q1 Y+0 R+Q3 DR-
25 L X+Q12
26 CHF Q4
27 L Y-Q3
28 L X-Q5 Y-Q11 R0
29 L Z+QR2 FMAX M30
30 END PGM H20 MM
