MODULE M
    CONST robtarget p10 := [[0,0,0],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    PROC main()
        MoveL p10, v100, fine, tool0;
        MoveL p99, v100, z10, tool0;
    ENDPROC
ENDMODULE
