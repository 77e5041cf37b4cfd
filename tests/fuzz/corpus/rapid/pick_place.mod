MODULE PickPlace
    ! Sample RAPID module for the program filter tests (written by hand).
    ! Comments mention [[1,2,3],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]] which must stay.
    PERS tooldata tGripper:=[TRUE,[[0,0,100],[1,0,0,0]],[1.2,[0,0,50],[1,0,0,0],0,0,0]];
    CONST robtarget pHome:=[[364.354,0,594],[0.5,0,0.866025,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget pPick  := [ [ 400.5, -120.25, 250 ], [ 0, 0.7071068, 0.7071068, 0 ], [ -1, 0, 0, 0 ], [ 9E9, 9E9, 9E9, 9E9, 9E9, 9E9 ] ];
    LOCAL PERS robtarget pPlace:=[[300,200,300],[0.5,0.5,0.5,0.5],[0,0,0,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    VAR robtarget pTemp;
    CONST robtarget pPath{2}:=[[[350,-50,400],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]],
                               [[350,50,400],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]]];
    CONST jointtarget jHome:=[[0,0,0,0,30,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST string sNote:="robtarget [[0,0,0],[1,0,0,0],[0,0,0,0],[0,0,0,0,0,0]] in a string";
    CONST num nSpeed:=100;

    PROC main()
        MoveAbsJ jHome, v1000, fine, tool0;
        MoveJ pHome, v1000, z50, tGripper;
        MoveL pPick, v200, fine, tGripper;  ! approach
        pTemp := pPick;
        MoveL [[410,-100,260.5],[0,0.7071068,0.7071068,0],[-1,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]], v100, fine, tGripper;
        MoveC pPath{1}, pPath{2}, v100, z10, tGripper;
        MoveL Offs(pPlace, 0, 0, 50), v200, z10, tGripper \WObj:=wobj0;
        MoveAbsJ [[10,-20,30,0,45,-90],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]]\NoEOffs, v500, fine, tool0;
        MoveJ pHome, v1000, fine, tGripper;
    ENDPROC
ENDMODULE
