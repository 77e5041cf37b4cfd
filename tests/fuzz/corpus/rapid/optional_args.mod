MODULE m
  CONST robtarget p10 := [[364.35,0,594],[0.5,0,0.866025,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    MoveL \Conc, p10, v100, fine, tool0\WObj:=wobj0\TLoad:=load0;
    MoveL p10, v100, z10, tool0\WObj:=wobj0;
  ENDPROC
ENDMODULE
