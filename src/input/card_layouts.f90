!> Card layouts as data: the fields of a keyword's cards (name, columns of the standard fixed
!> format, type, default, required) in one table, LAYOUTS, as the LS-DYNA manual tabulates them.
!> A keyword reader asks read_layout_card for a card and takes the values by name (real_field,
!> int_field); what a value means and which values are wrong stays in the reader (the semantic
!> checks). doc/keywords.md gives the same fields in its tables, and
!> tests/decks/test_card_layouts.py checks the two against each other. Columns are those of
!> the standard format; the long (LONG=/I10) and free (comma) formats follow from the fields'
!> order (mefem_cards' split_card).
!>
!> Keywords read through the table: *CONTROL_TERMINATION, *CONTROL_SOLUTION,
!> *CONTROL_HOURGLASS, *CONTROL_TIMESTEP (cards 1, 2), *CONTROL_IMPLICIT_GENERAL,
!> *CONTROL_IMPLICIT_SOLUTION (cards 1, 2), *CONTROL_IMPLICIT_AUTO, *DATABASE_BINARY_D3PLOT,
!> *DATABASE_BINARY_D3DUMP (whose card *DATABASE_BINARY_RUNRSF shares) and *DATABASE_GLSTAT (whose card *DATABASE_RCFORC and *DATABASE_NODOUT share),
!> *MEFEM_ENRICHMENT; the materials *MAT_ELASTIC, *MAT_PIECEWISE_LINEAR_PLASTICITY (cards 1-4),
!> *MAT_POWER_LAW_PLASTICITY and *MAT_PLASTIC_KINEMATIC (cards 1-2), *MAT_JOHNSON_COOK
!> (cards 1-4), *MAT_SIMPLIFIED_JOHNSON_COOK (cards 1-2), *MAT_MOONEY-RIVLIN_RUBBER and
!> *MAT_RIGID (cards 1-2), *MAT_ADD_EROSION (cards 1-2); *SECTION_SOLID, *SECTION_SHELL and
!> *HOURGLASS; the cards of the contacts (CONTACT_AUTOMATIC_SURFACE_TO_
!> SURFACE: cards 1-3, the eroding contacts' card 4, and the optional cards A, B, C as cards
!> 101, 102, 103), which all *CONTACT_ keywords read share; *BOUNDARY_SPC_NODE/_SET and
!> *BOUNDARY_PRESCRIBED_MOTION_NODE/_SET/_RIGID (their first field named by the form: NID, NSID
!> or PID, first_name); *LOAD_NODE_POINT/_SET; *DEFINE_CURVE (card 2: each point card),
!> *DEFINE_TABLE (card 2: each value card), *DEFINE_CURVE_SMOOTH; *INITIAL_VELOCITY (cards
!> 1-3), *INITIAL_VELOCITY_NODE, *INITIAL_VELOCITY_GENERATION (cards 1-2); the tiebreak
!> contacts' card 4 (*CONTACT_TIEBREAK_SURFACE_TO_SURFACE, _NODES_TO_SURFACE,
!> *CONTACT_AUTOMATIC_(ONE_WAY_)SURFACE_TO_SURFACE_TIEBREAK); *LOAD_SEGMENT, *LOAD_SEGMENT_SET,
!> *LOAD_BODY_X/Y/Z (one layout, LOAD_BODY_X), *LOAD_BODY_PARTS; *CONSTRAINED_GLOBAL,
!> _RIGID_BODIES, _EXTRA_NODES_NODE/_SET (NSID named by the form, form_name),
!> _NODAL_RIGID_BODY and _SPOTWELD (its data card); card 1 of every set (SID DA1-DA4, one
!> layout, SET_NODE; its text field SOLVER: text_after); *ELEMENT_MASS(_NODE_SET) and
!> *ELEMENT_MASS_PART(_SET) (8- and 16-column fields); *PART (card 2, the _CONTACT card 3) and
!> *PART_INERTIA (cards 3-5); *DEFINE_BOX, *DEFINE_COORDINATE_SYSTEM (cards 1-2),
!> *DEFINE_COORDINATE_VECTOR, *DEFINE_VECTOR, *DEFINE_VECTOR_NODES; *RIGIDWALL_PLANAR (cards
!> 1-2) and *RIGIDWALL_GEOMETRIC_FLAT (cards 1-4: 3 the flat wall's, 4 the MOTION card), whose
!> _PRISM, _CYLINDER and _SPHERE forms have their own card 3.
module mefem_card_layouts
  use mefem_kinds, only: wp
  use mefem_cards, only: reader_t, card_t, split_card, get_int, get_real, MAX_FIELDS
  use mefem_errors, only: fatal_local
  implicit none
  private

  public :: read_layout_card, real_field, int_field, layout_default

  !> One field of a card: keyword (without the '*'), card number, name, columns of the
  !> standard format, type ('I' integer, 'F' real), the value of a blank field, required, and
  !> whether a 0 means the default too.
  type, public :: field_layout_t
    character(len=48) :: keyword = ''
    integer :: card = 1
    character(len=8) :: name = ''
    integer :: first_column = 1
    integer :: last_column = 10
    character(len=1) :: kind = 'F'
    real(wp) :: default = 0.0_wp
    logical :: required = .false.
    logical :: zero_is_default = .false.   !< LS-DYNA's "0 = default": a 0 takes the default
  end type field_layout_t

  !> The values of one card read through its layout, by field name.
  type, public :: card_fields_t
    integer :: n = 0                                   !< fields
    character(len=8) :: name(MAX_FIELDS) = ''          !< their names
    real(wp) :: value(MAX_FIELDS) = 0.0_wp             !< their values (integers exactly)
  end type card_fields_t

  !> The layout of the card read last (read_layout_card): a keyword's repeated cards (a list
  !> of initial velocities, of table values) find their fields without a scan of the table.
  type :: layout_cache_t
    character(len=48) :: keyword = ''
    integer :: card = -1
    integer :: n = 0, nslot = 0
    integer :: rows(MAX_FIELDS) = 0, slot(MAX_FIELDS) = 0, widths(MAX_FIELDS) = 0
  end type layout_cache_t
  type(layout_cache_t) :: last

  integer, parameter :: N_LAYOUT_FIELDS = 520

  !> The table (doc/keywords.md has the same fields; tests/decks/test_card_layouts.py):
  !> keyword, card, field, first and last column, type, default, required, 0 = default; in
  !> four parts (a statement has at most 255 continuation lines): the controls, output,
  !> sections and contacts; the materials; the conditions, curves, loads and constraints; the
  !> sets, masses, parts, coordinate systems, vectors, boxes and rigid walls.
  type(field_layout_t), parameter :: LAYOUTS_MODEL(120) = [ &
    field_layout_t('CONTROL_TERMINATION', 1, 'ENDTIM', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_TERMINATION', 1, 'ENDCYC', 11, 20, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_TERMINATION', 1, 'DTMIN', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_TERMINATION', 1, 'ENDENG', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_TERMINATION', 1, 'ENDMAS', 41, 50, 'F', 1.0e8_wp, .false., .false.), &
    field_layout_t('CONTROL_SOLUTION', 1, 'SOLN', 1, 10, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_SOLUTION', 1, 'NLQ', 11, 20, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_SOLUTION', 1, 'ISNAN', 21, 30, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_SOLUTION', 1, 'LCINT', 31, 40, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_SOLUTION', 1, 'LCACC', 41, 50, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_SOLUTION', 1, 'NCDCF', 51, 60, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_SOLUTION', 1, 'NOCOP', 61, 70, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_HOURGLASS', 1, 'IHQ', 1, 10, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_HOURGLASS', 1, 'QH', 11, 20, 'F', 0.1_wp, .false., .true.), &
    field_layout_t('CONTROL_TIMESTEP', 1, 'DTINIT', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_TIMESTEP', 1, 'TSSFAC', 11, 20, 'F', 0.9_wp, .false., .true.), &
    field_layout_t('CONTROL_TIMESTEP', 1, 'ISDO', 21, 30, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_TIMESTEP', 1, 'TSLIMT', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_TIMESTEP', 1, 'DT2MS', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_TIMESTEP', 1, 'LCTM', 51, 60, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_TIMESTEP', 1, 'ERODE', 61, 70, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_TIMESTEP', 1, 'MS1ST', 71, 80, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_TIMESTEP', 2, 'DT2MSF', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_TIMESTEP', 2, 'DT2MSLC', 11, 20, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_TIMESTEP', 2, 'IMSCL', 21, 30, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_TIMESTEP', 2, 'RMSCL', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_IMPLICIT_GENERAL', 1, 'IMFLAG', 1, 10, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_IMPLICIT_GENERAL', 1, 'DT0', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_IMPLICIT_GENERAL', 1, 'IMFORM', 21, 30, 'I', 2.0_wp, .false., .true.), &
    field_layout_t('CONTROL_IMPLICIT_GENERAL', 1, 'NSBS', 31, 40, 'I', 1.0_wp, .false., .true.), &
    field_layout_t('CONTROL_IMPLICIT_GENERAL', 1, 'IGS', 41, 50, 'I', 2.0_wp, .false., .true.), &
    field_layout_t('CONTROL_IMPLICIT_SOLUTION', 1, 'NSOLVR', 1, 10, 'I', 12.0_wp, .false., .true.), &
    field_layout_t('CONTROL_IMPLICIT_SOLUTION', 1, 'ILIMIT', 11, 20, 'I', 11.0_wp, .false., .true.), &
    field_layout_t('CONTROL_IMPLICIT_SOLUTION', 1, 'MAXREF', 21, 30, 'I', 15.0_wp, .false., .true.), &
    field_layout_t('CONTROL_IMPLICIT_SOLUTION', 1, 'DCTOL', 31, 40, 'F', 0.001_wp, .false., .true.), &
    field_layout_t('CONTROL_IMPLICIT_SOLUTION', 1, 'ECTOL', 41, 50, 'F', 0.01_wp, .false., .true.), &
    field_layout_t('CONTROL_IMPLICIT_SOLUTION', 1, 'RCTOL', 51, 60, 'F', 1.0e10_wp, .false., .true.), &
    field_layout_t('CONTROL_IMPLICIT_SOLUTION', 1, 'LSTOL', 61, 70, 'F', 0.9_wp, .false., .true.), &
    field_layout_t('CONTROL_IMPLICIT_SOLUTION', 1, 'ABSTOL', 71, 80, 'F', 1.0e-10_wp, .false., .true.), &
    field_layout_t('CONTROL_IMPLICIT_SOLUTION', 2, 'DNORM', 1, 10, 'I', 2.0_wp, .false., .true.), &
    field_layout_t('CONTROL_IMPLICIT_SOLUTION', 2, 'DIVERG', 11, 20, 'I', 1.0_wp, .false., .true.), &
    field_layout_t('CONTROL_IMPLICIT_SOLUTION', 2, 'ISTIF', 21, 30, 'I', 1.0_wp, .false., .true.), &
    field_layout_t('CONTROL_IMPLICIT_SOLUTION', 2, 'NLPRINT', 31, 40, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_IMPLICIT_SOLUTION', 2, 'NLNORM', 41, 50, 'I', 2.0_wp, .false., .true.), &
    field_layout_t('CONTROL_IMPLICIT_AUTO', 1, 'IAUTO', 1, 10, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_IMPLICIT_AUTO', 1, 'ITEOPT', 11, 20, 'I', 11.0_wp, .false., .true.), &
    field_layout_t('CONTROL_IMPLICIT_AUTO', 1, 'ITEWIN', 21, 30, 'I', 5.0_wp, .false., .true.), &
    field_layout_t('CONTROL_IMPLICIT_AUTO', 1, 'DTMIN', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_IMPLICIT_AUTO', 1, 'DTMAX', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_IMPLICIT_AUTO', 1, 'DTEXP', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_IMPLICIT_AUTO', 1, 'KFAIL', 61, 70, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTROL_IMPLICIT_AUTO', 1, 'KCYCLE', 71, 80, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('DATABASE_BINARY_D3PLOT', 1, 'DT', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DATABASE_BINARY_D3PLOT', 1, 'LCDT', 11, 20, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('DATABASE_BINARY_D3PLOT', 1, 'BEAM', 21, 30, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('DATABASE_BINARY_D3PLOT', 1, 'NPLTC', 31, 40, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('DATABASE_BINARY_D3PLOT', 1, 'PSETID', 41, 50, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('DATABASE_BINARY_D3DUMP', 1, 'CYCL', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DATABASE_BINARY_D3DUMP', 1, 'LCDT', 11, 20, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('DATABASE_BINARY_D3DUMP', 1, 'BEAM', 21, 30, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('DATABASE_BINARY_D3DUMP', 1, 'NPLTC', 31, 40, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('DATABASE_BINARY_D3DUMP', 1, 'PSETID', 41, 50, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('DATABASE_BINARY_D3DUMP', 1, 'CID', 51, 60, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('DATABASE_BINARY_D3DUMP', 1, 'NSKIP', 61, 70, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('DATABASE_GLSTAT', 1, 'DT', 1, 10, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('MEFEM_ENRICHMENT', 1, 'SUPPORT', 1, 10, 'F', 1.5_wp, .false., .true.), &
    field_layout_t('MEFEM_ENRICHMENT', 1, 'BASIS', 11, 20, 'I', 1.0_wp, .false., .true.), &
    field_layout_t('MEFEM_ENRICHMENT', 1, 'BMASS', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('HOURGLASS', 1, 'HGID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('HOURGLASS', 1, 'IHQ', 11, 20, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('HOURGLASS', 1, 'QM', 21, 30, 'F', 0.1_wp, .false., .true.), &
    field_layout_t('HOURGLASS', 1, 'IBQ', 31, 40, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('HOURGLASS', 1, 'Q1', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('HOURGLASS', 1, 'Q2', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('HOURGLASS', 1, 'QB', 61, 70, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('HOURGLASS', 1, 'QW', 71, 80, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('SECTION_SOLID', 1, 'SECID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('SECTION_SOLID', 1, 'ELFORM', 11, 20, 'I', 1.0_wp, .false., .false.), &
    field_layout_t('SECTION_SOLID', 1, 'AET', 21, 30, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('SECTION_SHELL', 1, 'SECID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('SECTION_SHELL', 1, 'ELFORM', 11, 20, 'I', 2.0_wp, .false., .false.), &
    field_layout_t('SECTION_SHELL', 1, 'SHRF', 21, 30, 'F', 1.0_wp, .false., .false.), &
    field_layout_t('SECTION_SHELL', 1, 'NIP', 31, 40, 'I', 2.0_wp, .false., .false.), &
    field_layout_t('SECTION_SHELL', 1, 'ICOMP', 61, 70, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('SECTION_SHELL', 2, 'T1', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('SECTION_SHELL', 2, 'T2', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('SECTION_SHELL', 2, 'T3', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('SECTION_SHELL', 2, 'T4', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 1, 'SURFA', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 1, 'SURFB', 11, 20, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 1, 'SURFATYP', 21, 30, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 1, 'SURFBTYP', 31, 40, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 1, 'SABOXID', 41, 50, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 1, 'SBBOXID', 51, 60, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 1, 'SAPR', 61, 70, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 1, 'SBPR', 71, 80, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 2, 'FS', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 2, 'FD', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 2, 'DC', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 2, 'VC', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 2, 'VDC', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 2, 'PENCHK', 51, 60, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 2, 'BT', 61, 70, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 2, 'DT', 71, 80, 'F', 1.0e20_wp, .false., .true.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 3, 'SFSA', 1, 10, 'F', 1.0_wp, .false., .true.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 3, 'SFSB', 11, 20, 'F', 1.0_wp, .false., .true.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 3, 'SAST', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 3, 'SBST', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 3, 'SFSAT', 41, 50, 'F', 1.0_wp, .false., .true.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 3, 'SFSBT', 51, 60, 'F', 1.0_wp, .false., .true.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 3, 'FSF', 61, 70, 'F', 1.0_wp, .false., .true.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 3, 'VSF', 71, 80, 'F', 1.0_wp, .false., .true.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 4, 'ISYM', 1, 10, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 4, 'EROSOP', 11, 20, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 4, 'IADJ', 21, 30, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 101, 'SOFT', 1, 10, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 101, 'SOFSCL', 11, 20, 'F', 0.1_wp, .false., .true.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 102, 'PENMAX', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 103, 'IGAP', 1, 10, 'I', 1.0_wp, .false., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', 103, 'IGNORE', 11, 20, 'I', 0.0_wp, .false., .false.)]
  type(field_layout_t), parameter :: LAYOUTS_MATERIALS(128) = [ &
    field_layout_t('MAT_ELASTIC', 1, 'MID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('MAT_ELASTIC', 1, 'RO', 11, 20, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('MAT_ELASTIC', 1, 'E', 21, 30, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('MAT_ELASTIC', 1, 'PR', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PIECEWISE_LINEAR_PLASTICITY', 1, 'MID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('MAT_PIECEWISE_LINEAR_PLASTICITY', 1, 'RO', 11, 20, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('MAT_PIECEWISE_LINEAR_PLASTICITY', 1, 'E', 21, 30, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('MAT_PIECEWISE_LINEAR_PLASTICITY', 1, 'PR', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PIECEWISE_LINEAR_PLASTICITY', 1, 'SIGY', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PIECEWISE_LINEAR_PLASTICITY', 1, 'ETAN', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PIECEWISE_LINEAR_PLASTICITY', 1, 'FAIL', 61, 70, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PIECEWISE_LINEAR_PLASTICITY', 2, 'C', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PIECEWISE_LINEAR_PLASTICITY', 2, 'P', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PIECEWISE_LINEAR_PLASTICITY', 2, 'LCSS', 21, 30, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PIECEWISE_LINEAR_PLASTICITY', 2, 'LCSR', 31, 40, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PIECEWISE_LINEAR_PLASTICITY', 2, 'VP', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PIECEWISE_LINEAR_PLASTICITY', 3, 'EPS1', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PIECEWISE_LINEAR_PLASTICITY', 3, 'EPS2', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PIECEWISE_LINEAR_PLASTICITY', 3, 'EPS3', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PIECEWISE_LINEAR_PLASTICITY', 3, 'EPS4', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PIECEWISE_LINEAR_PLASTICITY', 3, 'EPS5', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PIECEWISE_LINEAR_PLASTICITY', 3, 'EPS6', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PIECEWISE_LINEAR_PLASTICITY', 3, 'EPS7', 61, 70, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PIECEWISE_LINEAR_PLASTICITY', 3, 'EPS8', 71, 80, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PIECEWISE_LINEAR_PLASTICITY', 4, 'ES1', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PIECEWISE_LINEAR_PLASTICITY', 4, 'ES2', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PIECEWISE_LINEAR_PLASTICITY', 4, 'ES3', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PIECEWISE_LINEAR_PLASTICITY', 4, 'ES4', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PIECEWISE_LINEAR_PLASTICITY', 4, 'ES5', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PIECEWISE_LINEAR_PLASTICITY', 4, 'ES6', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PIECEWISE_LINEAR_PLASTICITY', 4, 'ES7', 61, 70, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PIECEWISE_LINEAR_PLASTICITY', 4, 'ES8', 71, 80, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_POWER_LAW_PLASTICITY', 1, 'MID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('MAT_POWER_LAW_PLASTICITY', 1, 'RO', 11, 20, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('MAT_POWER_LAW_PLASTICITY', 1, 'E', 21, 30, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('MAT_POWER_LAW_PLASTICITY', 1, 'PR', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_POWER_LAW_PLASTICITY', 1, 'K', 41, 50, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('MAT_POWER_LAW_PLASTICITY', 1, 'N', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_POWER_LAW_PLASTICITY', 1, 'SRC', 61, 70, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_POWER_LAW_PLASTICITY', 1, 'SRP', 71, 80, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_POWER_LAW_PLASTICITY', 2, 'SIGY', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_POWER_LAW_PLASTICITY', 2, 'VP', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_POWER_LAW_PLASTICITY', 2, 'EPSF', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PLASTIC_KINEMATIC', 1, 'MID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('MAT_PLASTIC_KINEMATIC', 1, 'RO', 11, 20, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('MAT_PLASTIC_KINEMATIC', 1, 'E', 21, 30, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('MAT_PLASTIC_KINEMATIC', 1, 'PR', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PLASTIC_KINEMATIC', 1, 'SIGY', 41, 50, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('MAT_PLASTIC_KINEMATIC', 1, 'ETAN', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PLASTIC_KINEMATIC', 1, 'BETA', 61, 70, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PLASTIC_KINEMATIC', 2, 'SRC', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PLASTIC_KINEMATIC', 2, 'SRP', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PLASTIC_KINEMATIC', 2, 'FS', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_PLASTIC_KINEMATIC', 2, 'VP', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_JOHNSON_COOK', 1, 'MID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('MAT_JOHNSON_COOK', 1, 'RO', 11, 20, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('MAT_JOHNSON_COOK', 1, 'G', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_JOHNSON_COOK', 1, 'E', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_JOHNSON_COOK', 1, 'PR', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_JOHNSON_COOK', 1, 'DTF', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_JOHNSON_COOK', 1, 'VP', 61, 70, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_JOHNSON_COOK', 1, 'RATEOP', 71, 80, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_JOHNSON_COOK', 2, 'A', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_JOHNSON_COOK', 2, 'B', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_JOHNSON_COOK', 2, 'N', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_JOHNSON_COOK', 2, 'C', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_JOHNSON_COOK', 2, 'M', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_JOHNSON_COOK', 2, 'TM', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_JOHNSON_COOK', 2, 'TR', 61, 70, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_JOHNSON_COOK', 2, 'EPSO', 71, 80, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_JOHNSON_COOK', 3, 'CP', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_JOHNSON_COOK', 3, 'PC', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_JOHNSON_COOK', 3, 'SPALL', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_JOHNSON_COOK', 3, 'IT', 31, 40, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_JOHNSON_COOK', 3, 'D1', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_JOHNSON_COOK', 3, 'D2', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_JOHNSON_COOK', 3, 'D3', 61, 70, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_JOHNSON_COOK', 3, 'D4', 71, 80, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_JOHNSON_COOK', 4, 'D5', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_JOHNSON_COOK', 4, 'C2', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_JOHNSON_COOK', 4, 'EROD', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_JOHNSON_COOK', 4, 'EFMIN', 31, 40, 'F', 1.0e-6_wp, .false., .false.), &
    field_layout_t('MAT_JOHNSON_COOK', 4, 'NUMINT', 41, 50, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_MOONEY-RIVLIN_RUBBER', 1, 'MID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('MAT_MOONEY-RIVLIN_RUBBER', 1, 'RO', 11, 20, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('MAT_MOONEY-RIVLIN_RUBBER', 1, 'PR', 21, 30, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('MAT_MOONEY-RIVLIN_RUBBER', 1, 'A', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_MOONEY-RIVLIN_RUBBER', 1, 'B', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_MOONEY-RIVLIN_RUBBER', 1, 'REF', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_MOONEY-RIVLIN_RUBBER', 2, 'LCID', 31, 40, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_RIGID', 1, 'MID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('MAT_RIGID', 1, 'RO', 11, 20, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('MAT_RIGID', 1, 'E', 21, 30, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('MAT_RIGID', 1, 'PR', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_RIGID', 1, 'N', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_RIGID', 1, 'COUPLE', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_RIGID', 2, 'CMO', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_RIGID', 2, 'CON1', 11, 20, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_RIGID', 2, 'CON2', 21, 30, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_SIMPLIFIED_JOHNSON_COOK', 1, 'MID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('MAT_SIMPLIFIED_JOHNSON_COOK', 1, 'RO', 11, 20, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('MAT_SIMPLIFIED_JOHNSON_COOK', 1, 'E', 21, 30, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('MAT_SIMPLIFIED_JOHNSON_COOK', 1, 'PR', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_SIMPLIFIED_JOHNSON_COOK', 1, 'VP', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_SIMPLIFIED_JOHNSON_COOK', 2, 'A', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_SIMPLIFIED_JOHNSON_COOK', 2, 'B', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_SIMPLIFIED_JOHNSON_COOK', 2, 'N', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_SIMPLIFIED_JOHNSON_COOK', 2, 'C', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_SIMPLIFIED_JOHNSON_COOK', 2, 'PSFAIL', 41, 50, 'F', 1.0e28_wp, .false., .false.), &
    field_layout_t('MAT_SIMPLIFIED_JOHNSON_COOK', 2, 'SIGMAX', 51, 60, 'F', 1.0e28_wp, .false., .false.), &
    field_layout_t('MAT_SIMPLIFIED_JOHNSON_COOK', 2, 'SIGSAT', 61, 70, 'F', 1.0e28_wp, .false., .false.), &
    field_layout_t('MAT_SIMPLIFIED_JOHNSON_COOK', 2, 'EPSO', 71, 80, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_ADD_EROSION', 1, 'MID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('MAT_ADD_EROSION', 1, 'EXCL', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_ADD_EROSION', 1, 'MXPRES', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_ADD_EROSION', 1, 'MNEPS', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_ADD_EROSION', 1, 'EFFEPS', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_ADD_EROSION', 1, 'VOLEPS', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_ADD_EROSION', 1, 'NUMFIP', 61, 70, 'F', 1.0_wp, .false., .false.), &
    field_layout_t('MAT_ADD_EROSION', 1, 'NCS', 71, 80, 'I', 1.0_wp, .false., .false.), &
    field_layout_t('MAT_ADD_EROSION', 2, 'MNPRES', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_ADD_EROSION', 2, 'SIGP1', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_ADD_EROSION', 2, 'SIGVM', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_ADD_EROSION', 2, 'MXEPS', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_ADD_EROSION', 2, 'EPSSH', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_ADD_EROSION', 2, 'SIGTH', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_ADD_EROSION', 2, 'IMPULSE', 61, 70, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('MAT_ADD_EROSION', 2, 'FAILTM', 71, 80, 'F', 0.0_wp, .false., .false.)]
  type(field_layout_t), parameter :: LAYOUTS_CONDITIONS(145) = [ &
    field_layout_t('BOUNDARY_SPC_NODE', 1, 'NID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('BOUNDARY_SPC_NODE', 1, 'CID', 11, 20, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('BOUNDARY_SPC_NODE', 1, 'DOFX', 21, 30, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('BOUNDARY_SPC_NODE', 1, 'DOFY', 31, 40, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('BOUNDARY_SPC_NODE', 1, 'DOFZ', 41, 50, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('BOUNDARY_SPC_NODE', 1, 'DOFRX', 51, 60, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('BOUNDARY_SPC_NODE', 1, 'DOFRY', 61, 70, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('BOUNDARY_SPC_NODE', 1, 'DOFRZ', 71, 80, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('BOUNDARY_SPC_NODE', 2, 'BIRTH', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('BOUNDARY_SPC_NODE', 2, 'DEATH', 11, 20, 'F', 1.0e20_wp, .false., .true.), &
    field_layout_t('BOUNDARY_PRESCRIBED_MOTION_NODE', 1, 'NID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('BOUNDARY_PRESCRIBED_MOTION_NODE', 1, 'DOF', 11, 20, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('BOUNDARY_PRESCRIBED_MOTION_NODE', 1, 'VAD', 21, 30, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('BOUNDARY_PRESCRIBED_MOTION_NODE', 1, 'LCID', 31, 40, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('BOUNDARY_PRESCRIBED_MOTION_NODE', 1, 'SF', 41, 50, 'F', 1.0_wp, .false., .true.), &
    field_layout_t('BOUNDARY_PRESCRIBED_MOTION_NODE', 1, 'VID', 51, 60, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('BOUNDARY_PRESCRIBED_MOTION_NODE', 1, 'DEATH', 61, 70, 'F', 1.0e28_wp, .false., .true.), &
    field_layout_t('BOUNDARY_PRESCRIBED_MOTION_NODE', 1, 'BIRTH', 71, 80, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('LOAD_NODE_POINT', 1, 'NID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('LOAD_NODE_POINT', 1, 'DOF', 11, 20, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('LOAD_NODE_POINT', 1, 'LCID', 21, 30, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('LOAD_NODE_POINT', 1, 'SF', 31, 40, 'F', 1.0_wp, .false., .true.), &
    field_layout_t('LOAD_NODE_POINT', 1, 'CID', 41, 50, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_CURVE', 1, 'LCID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('DEFINE_CURVE', 1, 'SIDR', 11, 20, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_CURVE', 1, 'SFA', 21, 30, 'F', 1.0_wp, .false., .true.), &
    field_layout_t('DEFINE_CURVE', 1, 'SFO', 31, 40, 'F', 1.0_wp, .false., .true.), &
    field_layout_t('DEFINE_CURVE', 1, 'OFFA', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_CURVE', 1, 'OFFO', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_CURVE', 1, 'DATTYP', 61, 70, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_CURVE', 2, 'A', 1, 20, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('DEFINE_CURVE', 2, 'O', 21, 40, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('DEFINE_TABLE', 1, 'TBID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('DEFINE_TABLE', 1, 'SFA', 11, 20, 'F', 1.0_wp, .false., .true.), &
    field_layout_t('DEFINE_TABLE', 1, 'OFFA', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_TABLE', 2, 'VALUE', 1, 20, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('DEFINE_TABLE', 2, 'LCID', 21, 40, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_CURVE_SMOOTH', 1, 'LCID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('DEFINE_CURVE_SMOOTH', 1, 'SIDR', 11, 20, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_CURVE_SMOOTH', 1, 'DIST', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_CURVE_SMOOTH', 1, 'TSTART', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_CURVE_SMOOTH', 1, 'TEND', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_CURVE_SMOOTH', 1, 'TRISE', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_CURVE_SMOOTH', 1, 'V0', 61, 70, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_TIEBREAK_SURFACE_TO_SURFACE', 4, 'NFLS', 1, 10, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('CONTACT_TIEBREAK_SURFACE_TO_SURFACE', 4, 'SFLS', 11, 20, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('CONTACT_TIEBREAK_SURFACE_TO_SURFACE', 4, 'TBLCID', 21, 30, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_TIEBREAK_SURFACE_TO_SURFACE', 4, 'THKOFF', 31, 40, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_TIEBREAK_NODES_TO_SURFACE', 4, 'NFLF', 1, 10, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('CONTACT_TIEBREAK_NODES_TO_SURFACE', 4, 'SFLF', 11, 20, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('CONTACT_TIEBREAK_NODES_TO_SURFACE', 4, 'NEN', 21, 30, 'F', 2.0_wp, .false., .true.), &
    field_layout_t('CONTACT_TIEBREAK_NODES_TO_SURFACE', 4, 'MES', 31, 40, 'F', 2.0_wp, .false., .true.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_TIEBREAK', 4, 'OPTION', 1, 10, 'I', 1.0_wp, .false., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_TIEBREAK', 4, 'NFLS', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_TIEBREAK', 4, 'SFLS', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_TIEBREAK', 4, 'PARAM', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_TIEBREAK', 4, 'ERATEN', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_TIEBREAK', 4, 'ERATES', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_TIEBREAK', 4, 'CT2CN', 61, 70, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_TIEBREAK', 4, 'CN', 71, 80, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY', 1, 'NSID', 1, 10, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY', 1, 'NSIDEX', 11, 20, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY', 1, 'BOXID', 21, 30, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY', 1, 'IRIGID', 31, 40, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY', 1, 'ICID', 41, 50, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY', 2, 'VX', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY', 2, 'VY', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY', 2, 'VZ', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY', 2, 'VXR', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY', 2, 'VYR', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY', 2, 'VZR', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY', 3, 'VXE', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY', 3, 'VYE', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY', 3, 'VZE', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY_NODE', 1, 'NID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('INITIAL_VELOCITY_NODE', 1, 'VX', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY_NODE', 1, 'VY', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY_NODE', 1, 'VZ', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY_NODE', 1, 'VXR', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY_NODE', 1, 'VYR', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY_NODE', 1, 'VZR', 61, 70, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY_NODE', 1, 'ICID', 71, 80, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY_GENERATION', 1, 'ID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('INITIAL_VELOCITY_GENERATION', 1, 'STYP', 11, 20, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('INITIAL_VELOCITY_GENERATION', 1, 'OMEGA', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY_GENERATION', 1, 'VX', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY_GENERATION', 1, 'VY', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY_GENERATION', 1, 'VZ', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY_GENERATION', 1, 'IVATN', 61, 70, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY_GENERATION', 1, 'ICID', 71, 80, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY_GENERATION', 2, 'XC', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY_GENERATION', 2, 'YC', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY_GENERATION', 2, 'ZC', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY_GENERATION', 2, 'NX', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY_GENERATION', 2, 'NY', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY_GENERATION', 2, 'NZ', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY_GENERATION', 2, 'PHASE', 61, 70, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('INITIAL_VELOCITY_GENERATION', 2, 'IRIGID', 71, 80, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('LOAD_SEGMENT', 1, 'LCID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('LOAD_SEGMENT', 1, 'SF', 11, 20, 'F', 1.0_wp, .false., .true.), &
    field_layout_t('LOAD_SEGMENT', 1, 'AT', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('LOAD_SEGMENT', 1, 'N1', 31, 40, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('LOAD_SEGMENT', 1, 'N2', 41, 50, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('LOAD_SEGMENT', 1, 'N3', 51, 60, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('LOAD_SEGMENT', 1, 'N4', 61, 70, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('LOAD_SEGMENT', 1, 'N5', 71, 80, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('LOAD_SEGMENT_SET', 1, 'SSID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('LOAD_SEGMENT_SET', 1, 'LCID', 11, 20, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('LOAD_SEGMENT_SET', 1, 'SF', 21, 30, 'F', 1.0_wp, .false., .true.), &
    field_layout_t('LOAD_SEGMENT_SET', 1, 'AT', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('LOAD_BODY_X', 1, 'LCID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('LOAD_BODY_X', 1, 'SF', 11, 20, 'F', 1.0_wp, .false., .true.), &
    field_layout_t('LOAD_BODY_X', 1, 'LCIDDR', 21, 30, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('LOAD_BODY_X', 1, 'XC', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('LOAD_BODY_X', 1, 'YC', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('LOAD_BODY_X', 1, 'ZC', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('LOAD_BODY_X', 1, 'CID', 61, 70, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('LOAD_BODY_PARTS', 1, 'PSID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('CONSTRAINED_GLOBAL', 1, 'TC', 1, 10, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONSTRAINED_GLOBAL', 1, 'RC', 11, 20, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONSTRAINED_GLOBAL', 1, 'DIR', 21, 30, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('CONSTRAINED_GLOBAL', 1, 'X', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONSTRAINED_GLOBAL', 1, 'Y', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONSTRAINED_GLOBAL', 1, 'Z', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONSTRAINED_GLOBAL', 1, 'TOL', 61, 70, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONSTRAINED_RIGID_BODIES', 1, 'PIDL', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('CONSTRAINED_RIGID_BODIES', 1, 'PIDC', 11, 20, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('CONSTRAINED_RIGID_BODIES', 1, 'IFLAG', 21, 30, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONSTRAINED_EXTRA_NODES_NODE', 1, 'PID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('CONSTRAINED_EXTRA_NODES_NODE', 1, 'NID', 11, 20, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('CONSTRAINED_NODAL_RIGID_BODY', 1, 'PID', 1, 10, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONSTRAINED_NODAL_RIGID_BODY', 1, 'CID', 11, 20, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONSTRAINED_NODAL_RIGID_BODY', 1, 'NSID', 21, 30, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('CONSTRAINED_NODAL_RIGID_BODY', 1, 'PNODE', 31, 40, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONSTRAINED_NODAL_RIGID_BODY', 1, 'IPRT', 41, 50, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONSTRAINED_NODAL_RIGID_BODY', 1, 'DRFLAG', 51, 60, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONSTRAINED_NODAL_RIGID_BODY', 1, 'RRFLAG', 61, 70, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('CONSTRAINED_SPOTWELD', 1, 'N1', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('CONSTRAINED_SPOTWELD', 1, 'N2', 11, 20, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('CONSTRAINED_SPOTWELD', 1, 'SN', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONSTRAINED_SPOTWELD', 1, 'SS', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONSTRAINED_SPOTWELD', 1, 'N', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONSTRAINED_SPOTWELD', 1, 'M', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('CONSTRAINED_SPOTWELD', 1, 'TF', 61, 70, 'F', 1.0e20_wp, .false., .false.), &
    field_layout_t('CONSTRAINED_SPOTWELD', 1, 'EP', 71, 80, 'F', 1.0e20_wp, .false., .false.)]
  type(field_layout_t), parameter :: LAYOUTS_GEOMETRY(127) = [ &
    field_layout_t('SET_NODE', 1, 'SID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('SET_NODE', 1, 'DA1', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('SET_NODE', 1, 'DA2', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('SET_NODE', 1, 'DA3', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('SET_NODE', 1, 'DA4', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('ELEMENT_MASS', 1, 'EID', 1, 8, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('ELEMENT_MASS', 1, 'NID', 9, 16, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('ELEMENT_MASS', 1, 'MASS', 17, 32, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('ELEMENT_MASS', 1, 'PID', 33, 40, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('ELEMENT_MASS_PART', 1, 'PID', 1, 8, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('ELEMENT_MASS_PART', 1, 'ADDMASS', 9, 24, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('ELEMENT_MASS_PART', 1, 'FINMASS', 25, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('ELEMENT_MASS_PART', 1, 'LCID', 41, 56, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('PART', 2, 'PID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('PART', 2, 'SECID', 11, 20, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('PART', 2, 'MID', 21, 30, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('PART', 2, 'EOSID', 31, 40, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('PART', 2, 'HGID', 41, 50, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('PART', 3, 'FS', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('PART', 3, 'FD', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('PART', 3, 'DC', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('PART', 3, 'VC', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('PART', 3, 'OPTT', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('PART', 3, 'SFT', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('PART', 3, 'SSF', 61, 70, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('PART_INERTIA', 3, 'XC', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('PART_INERTIA', 3, 'YC', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('PART_INERTIA', 3, 'ZC', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('PART_INERTIA', 3, 'TM', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('PART_INERTIA', 3, 'IRCS', 41, 50, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('PART_INERTIA', 3, 'NODEID', 51, 60, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('PART_INERTIA', 4, 'IXX', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('PART_INERTIA', 4, 'IXY', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('PART_INERTIA', 4, 'IXZ', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('PART_INERTIA', 4, 'IYY', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('PART_INERTIA', 4, 'IYZ', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('PART_INERTIA', 4, 'IZZ', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('PART_INERTIA', 5, 'VTX', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('PART_INERTIA', 5, 'VTY', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('PART_INERTIA', 5, 'VTZ', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('PART_INERTIA', 5, 'VRX', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('PART_INERTIA', 5, 'VRY', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('PART_INERTIA', 5, 'VRZ', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_BOX', 1, 'BOXID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('DEFINE_BOX', 1, 'XMN', 11, 20, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('DEFINE_BOX', 1, 'XMX', 21, 30, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('DEFINE_BOX', 1, 'YMN', 31, 40, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('DEFINE_BOX', 1, 'YMX', 41, 50, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('DEFINE_BOX', 1, 'ZMN', 51, 60, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('DEFINE_BOX', 1, 'ZMX', 61, 70, 'F', 0.0_wp, .true., .false.), &
    field_layout_t('DEFINE_COORDINATE_SYSTEM', 1, 'CID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('DEFINE_COORDINATE_SYSTEM', 1, 'XO', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_COORDINATE_SYSTEM', 1, 'YO', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_COORDINATE_SYSTEM', 1, 'ZO', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_COORDINATE_SYSTEM', 1, 'XL', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_COORDINATE_SYSTEM', 1, 'YL', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_COORDINATE_SYSTEM', 1, 'ZL', 61, 70, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_COORDINATE_SYSTEM', 1, 'CIDL', 71, 80, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_COORDINATE_SYSTEM', 2, 'XP', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_COORDINATE_SYSTEM', 2, 'YP', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_COORDINATE_SYSTEM', 2, 'ZP', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_COORDINATE_VECTOR', 1, 'CID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('DEFINE_COORDINATE_VECTOR', 1, 'XX', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_COORDINATE_VECTOR', 1, 'YX', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_COORDINATE_VECTOR', 1, 'ZX', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_COORDINATE_VECTOR', 1, 'XV', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_COORDINATE_VECTOR', 1, 'YV', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_COORDINATE_VECTOR', 1, 'ZV', 61, 70, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_COORDINATE_VECTOR', 1, 'NID', 71, 80, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_VECTOR', 1, 'VID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('DEFINE_VECTOR', 1, 'XT', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_VECTOR', 1, 'YT', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_VECTOR', 1, 'ZT', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_VECTOR', 1, 'XH', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_VECTOR', 1, 'YH', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_VECTOR', 1, 'ZH', 61, 70, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_VECTOR', 1, 'CID', 71, 80, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('DEFINE_VECTOR_NODES', 1, 'VID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('DEFINE_VECTOR_NODES', 1, 'NODET', 11, 20, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('DEFINE_VECTOR_NODES', 1, 'NODEH', 21, 30, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('RIGIDWALL_PLANAR', 1, 'NSID', 1, 10, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_PLANAR', 1, 'NSIDEX', 11, 20, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_PLANAR', 1, 'BOXID', 21, 30, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_PLANAR', 1, 'OFFSET', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_PLANAR', 1, 'BIRTH', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_PLANAR', 1, 'DEATH', 51, 60, 'F', 1.0e20_wp, .false., .true.), &
    field_layout_t('RIGIDWALL_PLANAR', 1, 'RWKSF', 61, 70, 'F', 1.0_wp, .false., .true.), &
    field_layout_t('RIGIDWALL_PLANAR', 2, 'XT', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_PLANAR', 2, 'YT', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_PLANAR', 2, 'ZT', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_PLANAR', 2, 'XH', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_PLANAR', 2, 'YH', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_PLANAR', 2, 'ZH', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_PLANAR', 2, 'FRIC', 61, 70, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_PLANAR', 2, 'WVEL', 71, 80, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_FLAT', 1, 'NSID', 1, 10, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_FLAT', 1, 'NSIDEX', 11, 20, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_FLAT', 1, 'BOXID', 21, 30, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_FLAT', 1, 'BIRTH', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_FLAT', 1, 'DEATH', 41, 50, 'F', 1.0e20_wp, .false., .true.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_FLAT', 2, 'XT', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_FLAT', 2, 'YT', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_FLAT', 2, 'ZT', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_FLAT', 2, 'XH', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_FLAT', 2, 'YH', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_FLAT', 2, 'ZH', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_FLAT', 2, 'FRIC', 61, 70, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_FLAT', 3, 'XHEV', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_FLAT', 3, 'YHEV', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_FLAT', 3, 'ZHEV', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_FLAT', 3, 'LENL', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_FLAT', 3, 'LENM', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_FLAT', 4, 'LCID', 1, 10, 'I', 0.0_wp, .true., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_FLAT', 4, 'OPT', 11, 20, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_FLAT', 4, 'VX', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_FLAT', 4, 'VY', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_FLAT', 4, 'VZ', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_PRISM', 3, 'XHEV', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_PRISM', 3, 'YHEV', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_PRISM', 3, 'ZHEV', 21, 30, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_PRISM', 3, 'LENL', 31, 40, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_PRISM', 3, 'LENM', 41, 50, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_PRISM', 3, 'LENP', 51, 60, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_CYLINDER', 3, 'RADCYL', 1, 10, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_CYLINDER', 3, 'LENCYL', 11, 20, 'F', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_CYLINDER', 3, 'NSEGS', 21, 30, 'I', 0.0_wp, .false., .false.), &
    field_layout_t('RIGIDWALL_GEOMETRIC_SPHERE', 3, 'RADSPH', 1, 10, 'F', 0.0_wp, .false., .false.)]
  type(field_layout_t), parameter, public :: LAYOUTS(N_LAYOUT_FIELDS) = &
    [LAYOUTS_MODEL, LAYOUTS_MATERIALS, LAYOUTS_CONDITIONS, LAYOUTS_GEOMETRY]

contains

  !> Split card as card card_number of keyword's layout and read its fields (blank: the
  !> default; a blank required field, a bad number: the card's error, as get_int/get_real
  !> report them). Columns between two fields of the layout are skipped as fields of 10
  !> columns (the standard width), so that the free and long formats count them. Text fields
  !> after the layout's last field (text_after: their standard widths) are laid out too: the
  !> caller reads them with get_text as the card's last fields (card%nfields).
  subroutine read_layout_card(rd, card, keyword, card_number, fields, optional_here, first_name, &
                              form_name, text_after)
    type(reader_t), intent(in) :: rd                   !< reading state (format)
    type(card_t), intent(inout) :: card                !< the card
    character(len=*), intent(in) :: keyword            !< keyword of the table, without '*'
    integer, intent(in) :: card_number                 !< its card
    type(card_fields_t), intent(out) :: fields         !< the values by name
    character(len=*), intent(in), optional :: optional_here(:) !< required fields that this
                                                       !< form of the keyword does not need
    character(len=*), intent(in), optional :: first_name !< the first field's name in this
                                                       !< form (NSID for NID of a _SET form)
    character(len=*), intent(in), optional :: form_name(2) !< [table name, name in this form]:
                                                       !< a later field named by the form
    integer, intent(in), optional :: text_after(:)     !< widths of text fields after the last
    integer :: rows(MAX_FIELDS), slot(MAX_FIELDS), widths(MAX_FIELDS), k, n, nslot, value
    integer :: column
    type(field_layout_t) :: f
    if (keyword == last%keyword .and. card_number == last%card) then
      ! the same card as the last call (a keyword's repeated cards): its layout again
      n = last%n
      nslot = last%nslot
      rows(1:n) = last%rows(1:n)
      slot(1:n) = last%slot(1:n)
      widths(1:nslot) = last%widths(1:nslot)
    else
      ! the card's fields in column order; columns between them that are not read become
      ! fields of their own (10 columns each), skipped (as fields not read at the end are)
      n = 0
      nslot = 0
      column = 1
      do k = 1, N_LAYOUT_FIELDS
        if (LAYOUTS(k)%keyword /= keyword .or. LAYOUTS(k)%card /= card_number) cycle
        if (LAYOUTS(k)%first_column < column) call fatal_local( &
            'card_layouts: '//keyword//': the fields of a card must be in column order')
        do while (LAYOUTS(k)%first_column > column)
          call add_slot(min(10, LAYOUTS(k)%first_column - column))
        end do
        n = n + 1
        rows(n) = k
        call add_slot(LAYOUTS(k)%last_column - LAYOUTS(k)%first_column + 1)
        slot(n) = nslot
      end do
      last = layout_cache_t(keyword, card_number, n, nslot, rows, slot, widths)
    end if
    if (present(text_after)) then
      do k = 1, size(text_after)
        call add_slot(text_after(k))
      end do
    end if
    if (n == 0) call fatal_local('card_layouts: no layout for '//keyword)
    call split_card(rd, card, widths(1:nslot))
    fields%n = n
    do k = 1, n
      f = LAYOUTS(rows(k))
      if (present(optional_here)) then
        if (any(optional_here == f%name)) f%required = .false.
      end if
      if (present(first_name) .and. k == 1) f%name = first_name
      if (present(form_name)) then
        if (f%name == form_name(1)) f%name = form_name(2)
      end if
      fields%name(k) = f%name
      if (f%kind == 'I') then
        call get_int(card, slot(k), trim(f%name), value, default=nint(f%default), &
                     required=f%required)
        fields%value(k) = real(value, wp)
      else
        call get_real(card, slot(k), trim(f%name), fields%value(k), default=f%default, &
                      required=f%required)
      end if
      if (f%zero_is_default .and. fields%value(k) == 0.0_wp) fields%value(k) = f%default
    end do

  contains

    !> Append a field of width columns to the card's layout.
    subroutine add_slot(width)
      integer, intent(in) :: width                     !< its standard width
      if (nslot == MAX_FIELDS) call fatal_local('card_layouts: '//keyword// &
          ': more fields than a card holds')
      nslot = nslot + 1
      widths(nslot) = width
      column = column + width
    end subroutine add_slot

  end subroutine read_layout_card

  !> The default of field name of card card_number of keyword (what a blank field gives; for
  !> a card that is missing altogether).
  real(wp) function layout_default(keyword, card_number, name)
    character(len=*), intent(in) :: keyword            !< keyword of the table, without '*'
    integer, intent(in) :: card_number                 !< its card
    character(len=*), intent(in) :: name               !< field name
    integer :: k
    do k = 1, N_LAYOUT_FIELDS
      if (LAYOUTS(k)%keyword == keyword .and. LAYOUTS(k)%card == card_number .and. &
          LAYOUTS(k)%name == name) then
        layout_default = LAYOUTS(k)%default
        return
      end if
    end do
    call fatal_local('card_layouts: field '//name//' is not in the layout of '//keyword)
  end function layout_default

  !> The value of field name (a real field).
  real(wp) function real_field(fields, name)
    type(card_fields_t), intent(in) :: fields          !< read_layout_card's values
    character(len=*), intent(in) :: name               !< field name
    real_field = fields%value(position(fields, name))
  end function real_field

  !> The value of field name (an integer field).
  integer function int_field(fields, name)
    type(card_fields_t), intent(in) :: fields          !< read_layout_card's values
    character(len=*), intent(in) :: name               !< field name
    int_field = nint(fields%value(position(fields, name)))
  end function int_field

  !> Position of field name among the card's fields (a name not in the layout is a
  !> programming error: stop).
  integer function position(fields, name)
    type(card_fields_t), intent(in) :: fields          !< the card's values
    character(len=*), intent(in) :: name               !< field name
    do position = 1, fields%n
      if (fields%name(position) == name) return
    end do
    call fatal_local('card_layouts: field '//name//' is not in the card''s layout')
  end function position

end module mefem_card_layouts
