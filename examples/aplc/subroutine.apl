/* The manual's subroutine example (seed 002 Example 5, L2420-2473; spec
   aplc.md §3.2-§3.3). SBR_1's variable table IN1/IN2/OUT1 on V0/V1/V2
   (L2426-2430) and its body `ADD #IN1 #IN2 #OUT1` (L2435-2439); MAIN calls
   it with `CALL SBR_1 3 2 D0` under M0 (L2454-2455). With M0 ON, D0 = 3 + 2
   = 5 (L2465-2473). The manual shows the POU names and the table only as
   editor screens; this is their text form (contract §1.1 items 7-8). */
POU SBR_1
VAR
    IN1   IN   INT      // V0
    IN2   IN   INT      // V1
    OUT1  OUT  INT      // V2
END_VAR
LD SM0
ADD #IN1 #IN2 #OUT1

POU MAIN
LD M0
CALL SBR_1 3 2 D0
