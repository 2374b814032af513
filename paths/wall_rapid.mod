! Two layers of a 1200 mm x 40 mm stadium-shaped wall outline (straight sides joined by
! semicircles of radius 20 mm), written by hand for printwatt in the style of a Grasshopper /
! RobotStudio export: named robtargets, Offs(), MoveJ approach and retract (travel), MoveL straight
! sides at v100, MoveC end caps at a custom speeddata, z10 blends, a custom zonedata, fine at
! the end. Units: mm. Layer height 15 mm; the nozzle points down (q = [0,0,1,0]).
! Hand computation: print length per layer 2 x 1200 + 2 pi 20 = 2525.66 mm, plus 15 mm rise.
MODULE WallRapid
    CONST robtarget pHome := [[0,-20,200],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget p10 := [[-600,-20,15],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget p20 := [[600,-20,15],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget p25 := [[620,0,15],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget p30 := [[600,20,15],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget p40 := [[-600,20,15],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget p45 := [[-620,0,15],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST speeddata vCap := [80,500,5000,1000];
    CONST zonedata zCap := [FALSE,5,7.5,7.5,0.75,7.5,0.75];
    PERS tooldata tNozzle := [TRUE,[[0,0,350],[1,0,0,0]],[25,[0,0,150],[1,0,0,0],0,0,0]];

    PROC main()
        ConfL \Off;
        MoveJ pHome, v500, z50, tNozzle \WObj:=wobj0;
        MoveJ Offs(p10,0,0,50), v500, z20, tNozzle \WObj:=wobj0;
        MoveJ p10, v100, fine, tNozzle \WObj:=wobj0;
        SetDO doPump, 1;
        ! layer 1
        MoveL p20, v100, z10, tNozzle \WObj:=wobj0;
        MoveC p25, p30, vCap, zCap, tNozzle \WObj:=wobj0;
        MoveL p40, v100, z10, tNozzle \WObj:=wobj0;
        MoveC p45, p10, vCap, zCap, tNozzle \WObj:=wobj0;
        ! layer 2: rise 15 mm in place, then the same outline
        MoveL Offs(p10,0,0,15), v100 \V:=50, z10 \Z:=2, tNozzle \WObj:=wobj0;
        MoveL Offs(p20,0,0,15), v100, z10, tNozzle \WObj:=wobj0;
        MoveC Offs(p25,0,0,15), Offs(p30,0,0,15), vCap, zCap, tNozzle \WObj:=wobj0;
        MoveL Offs(p40,0,0,15), v100, z10, tNozzle \WObj:=wobj0;
        MoveC Offs(p45,0,0,15), Offs(p10,0,0,15), vCap, fine, tNozzle \WObj:=wobj0;
        SetDO doPump, 0;
        MoveJ Offs(p10,0,0,200), v500, fine, tNozzle \WObj:=wobj0;
    ENDPROC
ENDMODULE
