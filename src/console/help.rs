//! The help screens of the one console (docs/panel.md "Keys", docs/lathe.md "Keys"): every
//! key of the panel, the centre's two pages and a lathe's one with its key legend. The
//! keyboard map and the help screen belong to the console; the terminal and the window draw
//! these texts. Before stop 51 the centre's lived in the terminal's layout (the window took
//! them from there) and a lathe's in its console's view.

/// The help screen: every key of the panel.
pub const HELP: &[&str] = &[
    "novanc terminal panel: keys",
    "",
    "Operation mode selector 17   Alt+1 CONTINUOUS  Alt+2 AUTO  Alt+3 MDI",
    "                             Alt+4 DATA INPUT  Alt+5 HANDLE  Alt+6 STEP",
    "                             Alt+7 SINGLE BLOCK",
    "Data mode selector 16        F1 SEARCH  F2 PROGRAM READ  F3 PROGRAM REVISION",
    "                             F4 TOOL DATA READ  F5 TOOL DATA REVISION",
    "                             F6 T-CODE SETTING  F7 MDI",
    "Relay buttons                F9/Alt+s START  F10/Alt+p STOP (feed hold)",
    "                             F11/Alt+r RESET  F12/Alt+e EMERGENCY STOP",
    "Feed override                Alt+= up 10 %   Alt+- down 10 %",
    "Jog (CONTINUOUS, STEP)       arrows X and Y, PgUp/PgDn Z",
    "Handwheel (HANDLE)           arrows/PgUp/PgDn: 1 detent on that axis",
    "                             Alt+, Alt+. turn the wheel; Alt+w x1 x10 x100 x1000",
    "                             Alt+a the wheel's axis: X Y Z and the rotary A B C",
    "                             (CONTINUOUS, STEP: Alt+, Alt+. jog the wheel's axis)",
    "STEP increment               Alt+w: 0.001 0.01 0.1 1 mm (a CONTINUOUS tap: one step)",
    "Data keys (DATA INPUT, MDI)  type; Enter = EOB; Backspace = RUBOUT",
    "Tape reader                  type the file path, then Alt+t; START reads it",
    "Tape punch (PROGRAM READ)    type PATH (ISO code) or PATH EIA, then Alt+u",
    "G-code switches              Alt+b BLOCK DELETE  Alt+o OPTIONAL STOP (M01)",
    "Overrides, switches          Alt+f RPD Alt+[ ] SOV Alt+d DRY Alt+l MLK Alt+z ZNG",
    "Pages                        Ctrl-P POS  Ctrl-D PROG  Ctrl-O OFS  Ctrl-E MSG",
    "Other                        F8/Alt+h this help  Ctrl-L redraw  Ctrl-C/Alt+q quit",
    "F8 again: the editor commands and the page keys. Any other key closes the help",
    "and acts as on the panel (STOP, RESET and E-STOP too): no key is lost.",
];

/// The second help page: the editor commands with an example each, and the page keys.
pub const HELP_EDITOR: &[&str] = &[
    "novanc terminal panel: the editor commands (DATA INPUT, F3 F5 F7) and the pages",
    "",
    "nL   lines: 2L down two, 0L line start, -1L up one     L",
    "mM   move m characters: -5M back five                  M",
    "nK   kill through the nth EOB: K the rest of the line  K",
    "nD   delete n characters: -3D the three before        D",
    "Itext   insert: IP9 = (10, 20)*  (* is EOB)           I",
    "Stext   search (either case): Sdrl, 105$              S",
    "Cold$new  change: CDP20$DP22                           C",
    "nY   show n lines: 5Y                                  Y",
    "Several on a line: 2LCNH6$NH5  (a failed line changes nothing)",
    "Keys: arrows PgUp/PgDn Home/End move the pointer, Delete deletes after it",
    "",
    "Pages (any mode; the same key again goes back):",
    "  Ctrl-P POS   positions, feed, spindle, counters; X Enter zeroes rel X",
    "  Ctrl-D PROG  programs: Enter selects, C NAME copies, R NAME renames, D deletes",
    "  Ctrl-O OFS   tool offsets, then G54-G59: value Enter sets, Tab adds",
    "  Ctrl-E MSG   alarm and message history, newest first",
    "  Ctrl-G MODAL the G codes, F S T H D and offsets in force, overrides, switches",
    "  Ctrl-T I/O   outputs and inputs: P3 ON, P3 OFF or E2 4.5 Enter sets an input",
    "  Ctrl-U MACRO Fanuc #1-#33 #100-#199 #500-#999: #500=12.5 Enter sets",
    "MDI mode: a statement or a G-code line, Enter, F9; Up/Down recall 20",
    "",
    "F8 closes the help; any other key closes it and acts as on the panel.",
];

/// The key legend beside the plasma display (the terminal's).
pub const LATHE_KEYS: [&str; 13] = [
    "F9  START   F10 STOP",
    "F11 RESET   F12 E-STOP",
    "Tab CHANNEL  Ctrl-C quit",
    "Alt+2 AUTO  Alt+3 MDI",
    "Alt+4 DATA  Ctrl+O OFS",
    "Ctrl+E MSG  Ctrl+U MACRO",
    "Alt+1 CONT Alt+5 HANDLE",
    "Alt+6 STEP  Alt+7 SINGLE",
    "Alt+x FAULT Alt+n TARGET",
    "Alt+o M01   Alt+b /DEL",
    "Alt+= Alt+- FOV Alt+f RPD",
    "F8 help  Alt+t/u READ/PCH",
    "Alt+[ ] SOV  Alt+d DRY",
];

/// The help screen (the terminal's and the window's).
pub const LATHE_HELP: [&str; 20] = [
    "LATHE CONSOLE  (F8 or Alt+h: back; any other key closes this and acts)",
    "Tab / Alt+c   channel selector: the display, data keys and editor act on it",
    "F9  / Alt+s   START: begin the cycle (AUTO) or the MDI lines; resume after a stop",
    "F10 / Alt+p   STOP: feed hold on every channel",
    "F11 / Alt+r   RESET the selected channel (a fault or alarm); after E-STOP, the machine",
    "F12 / Alt+e   E-STOP: everything stops at once; Alt+0 HOME: the channel's reference return",
    "Alt+x         FAULT: stop the selected channel with the typed reason (else 'operator')",
    "Alt+n         part target: the typed number; in DATA, Alt+t reads the typed file into the channel, Alt+u punches it",
    "Alt+2/3/4     AUTO / MDI (Enter adds a line) / DATA (an editor line); Ctrl+O OFS (a value Enter, Tab adds)",
    "Ctrl+E        MSG: the alarm and message history, newest first, kept across restarts (Up/Down)",
    "Ctrl+U        MACRO: the channel's variables #1-#33, #100-#199, #500-#999; #500=12.5 Enter sets one",
    "Ctrl+G        MODAL: the channel's modal G codes, F, S, tool and the switches, read only",
    "Ctrl+P        POS: the channel's tool tip and its distance to go in the block, the parts and cycle time",
    "Alt+o, Alt+b  OPTIONAL STOP (M01), BLOCK DELETE (/); Alt+= / Alt+- feed override ±10 %",
    "The summary line: channel, state, current block or whom it waits for, parts/target",
    "Alt+7         SINGLE BLOCK: AUTO, every channel stops after each block; START runs the next",
    "Alt+1/5/6     CONTINUOUS (hold an arrow) / HANDLE (Alt+, Alt+. turn the wheel) / STEP (an increment)",
    "              Up/Down X+/X- (a radius), Left/Right Z-/Z+; Alt+w increment x1..x1000; in DATA the editor's cursor keys",
    "Alt+f, Alt+[] rapid override 100/50/25/F0, spindle override ±10 % (50-120); Alt+d DRY RUN; Alt+l MACHINE LOCK",
    "Ctrl-C or Alt+q quits; programs, MDI lines and the part counter are stored at every change",
];
