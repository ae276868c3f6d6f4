// A barcode reader on PORT1, free port (the APLC manual's §10.3 and RCV,
// §6.10.11): 9600 8N1, each code ends with CR (end character 13, SD120
// bit 8). RCV with SM0 re-arms the receiver once the previous code is in
// (RX enable SM121 OFF); the frame-received interrupt (event 37, enabled by
// SM55, §3.5) runs before MAIN in the next scan and keeps the code: D100
// codes read, D101 its length with the CR (SD127), D102 how it ended
// (SD125; RCV's re-arm clears it), D200.. its characters one per word.
POU MAIN
LD SM1
SET SM55
EI
LD SM0
RCV 1 D10 20
POU INT_0 EVENT 37
LD SM0
INC D100
MOV SD127 D101
MOV SD125 D102
BMOV D10 D200 20
