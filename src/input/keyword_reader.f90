!> The keyword reader: reads a deck into the model, dispatching each keyword to its handler.
!>
!> The registry below lists every keyword mefem reads (its base name, the options it takes
!> and its handler), the keywords it skips with one warning (output requests, cosmetic
!> settings, and settings with no counterpart in mefem's formulation, each with the reason
!> in the warning) and the rule for everything else: a keyword that is not known is an
!> error, because ignoring it could silently change the analysis.
!> A keyword name is matched against the longest registered base name; what follows it
!> (`_TITLE`, `_ID`, `_SET`, `_GENERATE` ...) are options, each checked against the list.
module mefem_keyword_reader
  use mefem_errors, only: input_error, input_error_count, warn, warn_once
  use mefem_strings, only: to_upper, starts_with
  use mefem_deck_source, only: deck_open, deck_next_line, deck_close, location, &
                               LINE_KEYWORD, LINE_DATA, LINE_EOF
  use mefem_cards, only: reader_t, card_t, next_card, keyword_error, keyword_where
  use mefem_model, only: model_t, ON_NODE, ON_NODE_SET, ON_PART, WALL_FLAT, WALL_PRISM, &
                         WALL_CYLINDER, WALL_SPHERE, SYSTEM_BY_POINTS, SYSTEM_BY_VECTORS, &
                         SYSTEM_BY_NODES, SET_SOLID, SET_SHELL
  use mefem_read_mesh, only: read_node, read_element_solid, read_element_shell, read_part, &
                             read_section_solid, read_section_shell, read_hourglass, &
                             read_element_mass, read_element_mass_part
  use mefem_read_controls, only: read_keyword_card, read_title, read_parameter, &
                                 read_parameter_expression, &
                                 read_control_termination, read_control_timestep, &
                                 read_control_solution, read_control_hourglass, &
                                 read_control_implicit_general, &
                                 read_control_implicit_solution, read_control_implicit_auto, &
                                 read_database_binary_d3plot, read_database_interval, &
                                 read_database_history_node, read_mefem_enrichment, &
                                 DATABASE_GLSTAT, DATABASE_RCFORC, DATABASE_NODOUT, &
                                 read_database_restart, DATABASE_D3DUMP, DATABASE_RUNRSF
  use mefem_read_materials, only: read_mat_johnson_cook, read_mat_simplified_johnson_cook, &
                                  last_material_id, &
                                  read_mat_elastic, read_mat_piecewise_linear, &
                                  read_mat_power_law, read_mat_mooney_rivlin, read_mat_rigid, read_mat_add_erosion, &
                                  read_mat_plastic_kinematic
  use mefem_read_sets, only: read_set_node, read_set_part, read_set_segment, read_set_element
  use mefem_read_coordinates, only: read_define_coordinate, read_define_vector
  use mefem_read_conditions, only: read_boundary_spc, read_prescribed_motion, &
                                   read_define_curve, read_define_curve_smooth, read_define_box, &
                                   read_define_table, &
                                   read_constrained_global, read_load_node, read_load_segment, &
                                   read_load_segment_set, read_initial_velocity, &
                                   read_initial_velocity_node, read_initial_velocity_generation, &
                                   read_constrained_rigid_bodies, read_constrained_extra_nodes, &
                                   read_constrained_nodal_rigid_body, read_constrained_spotweld, &
                                   read_load_body, read_load_body_parts
  use mefem_read_contact, only: read_contact_surface_to_surface, read_rigidwall_planar, &
                                read_rigidwall_geometric, &
                                FORM_SURFACE_TO_SURFACE, FORM_SINGLE_SURFACE, &
                                FORM_NODES_TO_SURFACE, FORM_TIED, FORM_TIED_NODES, &
                                FORM_TRANSDUCER, FORM_TIEBREAK, FORM_TIEBREAK_NODES, &
                                FORM_TIEBREAK_AUTOMATIC
  implicit none
  private

  public :: read_deck

  ! handler codes
  integer, parameter :: H_NODE = 1, H_ELEMENT_SOLID = 2, H_ELEMENT_SHELL = 3, H_PART = 4, &
                        H_SECTION_SOLID = 5, H_SECTION_SHELL = 6, H_KEYWORD = 7, H_TITLE = 8, &
                        H_PARAMETER = 9, H_CONTROL_TERMINATION = 10
  integer, parameter :: H_MAT_ELASTIC = 11, H_MAT_PIECEWISE_LINEAR = 12, H_MAT_POWER_LAW = 13, &
                        H_MAT_MOONEY_RIVLIN = 14, H_MAT_RIGID = 15
  integer, parameter :: H_SET_NODE = 16, H_SET_PART = 17, H_SET_SEGMENT = 18
  integer, parameter :: H_SPC_NODE = 19, H_SPC_SET = 20, H_MOTION_NODE = 21, H_MOTION_SET = 22, &
                        H_MOTION_RIGID = 23, H_DEFINE_CURVE = 24, H_LOAD_NODE_POINT = 25, &
                        H_LOAD_NODE_SET = 26, H_LOAD_SEGMENT = 27, H_LOAD_SEGMENT_SET = 28, &
                        H_INITIAL_VELOCITY = 29, H_INITIAL_VELOCITY_NODE = 30, &
                        H_INITIAL_VELOCITY_GENERATION = 31
  integer, parameter :: H_CONTACT_SURFACE_TO_SURFACE = 32, H_RIGIDWALL_PLANAR = 33
  integer, parameter :: H_CONTROL_TIMESTEP = 34, H_CONTROL_IMPLICIT_GENERAL = 35, &
                        H_CONTROL_IMPLICIT_SOLUTION = 36, H_CONTROL_IMPLICIT_AUTO = 37, &
                        H_DATABASE_D3PLOT = 38, H_DATABASE_GLSTAT = 39, H_DATABASE_RCFORC = 40, &
                        H_DATABASE_NODOUT = 41, H_HISTORY_NODE = 42, H_HISTORY_NODE_SET = 43, &
                        H_MEFEM_ENRICHMENT = 44, H_PARAMETER_EXPRESSION = 45
  integer, parameter :: H_LOAD_BODY_X = 46, H_LOAD_BODY_Y = 47, H_LOAD_BODY_Z = 48, &
                        H_LOAD_BODY_PARTS = 49
  integer, parameter :: H_CONTROL_SOLUTION = 50, H_HOURGLASS = 51, H_CONTROL_HOURGLASS = 52, &
                        H_MAT_PLASTIC_KINEMATIC = 53, H_CONSTRAINED_RIGID_BODIES = 54, &
                        H_CONSTRAINED_EXTRA_NODES = 55, H_CONTACT_SINGLE_SURFACE = 56, &
                        H_CONTACT_NODES_TO_SURFACE = 57, H_CONTACT_TIED = 58, &
                        H_CONTACT_TRANSDUCER = 59, H_RIGIDWALL_FLAT = 60, &
                        H_RIGIDWALL_PRISM = 61, H_RIGIDWALL_CYLINDER = 62, H_RIGIDWALL_SPHERE = 63, &
                        H_MAT_JOHNSON_COOK = 64, H_MAT_SIMPLIFIED_JOHNSON_COOK = 65, &
                        H_CONSTRAINED_NODAL_RIGID_BODY = 66, H_CONSTRAINED_SPOTWELD = 67, &
                        H_ELEMENT_MASS = 68, H_ELEMENT_MASS_PART = 69, H_DEFINE_BOX = 70, &
                        H_CONSTRAINED_GLOBAL = 71, H_MAT_ADD_EROSION = 72, &
                        H_DEFINE_CURVE_SMOOTH = 73, H_DEFINE_TABLE = 74, &
                        H_DEFINE_COORDINATE_SYSTEM = 75, H_DEFINE_COORDINATE_VECTOR = 76, &
                        H_DEFINE_COORDINATE_NODES = 77, H_DEFINE_VECTOR = 78, &
                        H_SET_SOLID = 79, H_SET_SHELL = 80, H_CONTACT_TIEBREAK = 81, &
                        H_DATABASE_D3DUMP = 82, H_DATABASE_RUNRSF = 83

  !> Id read from the first card of a rejected keyword (skip_cards), 0 when none.
  integer :: rejected_id = 0

  !> One registered keyword.
  type :: keyword_entry_t
    character(len=56) :: base = ''       !< name without options, upper case, no '*'
    integer :: handler = 0               !< H_* code
    character(len=64) :: options = ''    !< options accepted, as ' OPT1 OPT2 '
  end type keyword_entry_t

  integer, parameter :: N_ENTRIES = 103
  type(keyword_entry_t), parameter :: REGISTRY(N_ENTRIES) = [ &
    keyword_entry_t('NODE', H_NODE, ' '), &
    keyword_entry_t('ELEMENT_SOLID', H_ELEMENT_SOLID, ' '), &
    keyword_entry_t('ELEMENT_SHELL', H_ELEMENT_SHELL, ' '), &
    keyword_entry_t('ELEMENT_MASS', H_ELEMENT_MASS, ' NODE SET '), &
    keyword_entry_t('ELEMENT_MASS_PART', H_ELEMENT_MASS_PART, ' SET '), &
    keyword_entry_t('PART', H_PART, ' CONTACT INERTIA '), &
    keyword_entry_t('SECTION_SOLID', H_SECTION_SOLID, ' TITLE '), &
    keyword_entry_t('SECTION_SHELL', H_SECTION_SHELL, ' TITLE '), &
    keyword_entry_t('HOURGLASS', H_HOURGLASS, ' TITLE '), &
    keyword_entry_t('KEYWORD', H_KEYWORD, ' '), &
    keyword_entry_t('TITLE', H_TITLE, ' '), &
    keyword_entry_t('PARAMETER', H_PARAMETER, ' '), &
    keyword_entry_t('PARAMETER_EXPRESSION', H_PARAMETER_EXPRESSION, ' '), &
    keyword_entry_t('CONTROL_TERMINATION', H_CONTROL_TERMINATION, ' '), &
    ! materials, by name and by number
    keyword_entry_t('MAT_ELASTIC', H_MAT_ELASTIC, ' TITLE '), &
    keyword_entry_t('MAT_001', H_MAT_ELASTIC, ' TITLE '), &
    keyword_entry_t('MAT_PIECEWISE_LINEAR_PLASTICITY', H_MAT_PIECEWISE_LINEAR, ' TITLE '), &
    keyword_entry_t('MAT_024', H_MAT_PIECEWISE_LINEAR, ' TITLE '), &
    keyword_entry_t('MAT_POWER_LAW_PLASTICITY', H_MAT_POWER_LAW, ' TITLE '), &
    keyword_entry_t('MAT_018', H_MAT_POWER_LAW, ' TITLE '), &
    keyword_entry_t('MAT_PLASTIC_KINEMATIC', H_MAT_PLASTIC_KINEMATIC, ' TITLE '), &
    keyword_entry_t('MAT_JOHNSON_COOK', H_MAT_JOHNSON_COOK, ' TITLE '), &
    keyword_entry_t('MAT_015', H_MAT_JOHNSON_COOK, ' TITLE '), &
    keyword_entry_t('MAT_SIMPLIFIED_JOHNSON_COOK', H_MAT_SIMPLIFIED_JOHNSON_COOK, ' TITLE '), &
    keyword_entry_t('MAT_098', H_MAT_SIMPLIFIED_JOHNSON_COOK, ' TITLE '), &
    keyword_entry_t('MAT_003', H_MAT_PLASTIC_KINEMATIC, ' TITLE '), &
    keyword_entry_t('MAT_MOONEY-RIVLIN_RUBBER', H_MAT_MOONEY_RIVLIN, ' TITLE '), &
    keyword_entry_t('MAT_MOONEY_RIVLIN_RUBBER', H_MAT_MOONEY_RIVLIN, ' TITLE '), &
    keyword_entry_t('MAT_027', H_MAT_MOONEY_RIVLIN, ' TITLE '), &
    keyword_entry_t('MAT_RIGID', H_MAT_RIGID, ' TITLE '), &
    keyword_entry_t('MAT_020', H_MAT_RIGID, ' TITLE '), &
    ! sets (*SET_NODE and *SET_PART are the older names of the _LIST forms)
    keyword_entry_t('SET_NODE', H_SET_NODE, ' LIST GENERATE GENERAL TITLE '), &
    keyword_entry_t('SET_PART', H_SET_PART, ' LIST GENERAL TITLE '), &
    keyword_entry_t('SET_SEGMENT', H_SET_SEGMENT, ' GENERAL TITLE '), &
    keyword_entry_t('SET_SOLID', H_SET_SOLID, ' LIST GENERATE TITLE '), &
    keyword_entry_t('SET_SHELL', H_SET_SHELL, ' LIST GENERATE TITLE '), &
    ! boundary conditions, curves, loads, initial conditions
    keyword_entry_t('BOUNDARY_SPC_NODE', H_SPC_NODE, ' ID BIRTH DEATH '), &
    keyword_entry_t('BOUNDARY_SPC_SET', H_SPC_SET, ' ID BIRTH DEATH '), &
    keyword_entry_t('BOUNDARY_PRESCRIBED_MOTION_NODE', H_MOTION_NODE, ' ID '), &
    keyword_entry_t('BOUNDARY_PRESCRIBED_MOTION_SET', H_MOTION_SET, ' ID '), &
    keyword_entry_t('BOUNDARY_PRESCRIBED_MOTION_RIGID', H_MOTION_RIGID, ' ID '), &
    keyword_entry_t('DEFINE_CURVE', H_DEFINE_CURVE, ' TITLE '), &
    keyword_entry_t('DEFINE_CURVE_SMOOTH', H_DEFINE_CURVE_SMOOTH, ' TITLE '), &
    keyword_entry_t('DEFINE_TABLE', H_DEFINE_TABLE, ' TITLE '), &
    keyword_entry_t('DEFINE_COORDINATE_SYSTEM', H_DEFINE_COORDINATE_SYSTEM, ' TITLE '), &
    keyword_entry_t('DEFINE_COORDINATE_VECTOR', H_DEFINE_COORDINATE_VECTOR, ' TITLE '), &
    keyword_entry_t('DEFINE_COORDINATE_NODES', H_DEFINE_COORDINATE_NODES, ' TITLE '), &
    keyword_entry_t('DEFINE_VECTOR', H_DEFINE_VECTOR, ' NODES TITLE '), &
    keyword_entry_t('DEFINE_BOX', H_DEFINE_BOX, ' TITLE '), &
    keyword_entry_t('MAT_ADD_EROSION', H_MAT_ADD_EROSION, ' TITLE '), &
    keyword_entry_t('LOAD_NODE_POINT', H_LOAD_NODE_POINT, ' '), &
    keyword_entry_t('LOAD_NODE_SET', H_LOAD_NODE_SET, ' '), &
    keyword_entry_t('LOAD_SEGMENT', H_LOAD_SEGMENT, ' ID '), &
    keyword_entry_t('LOAD_SEGMENT_SET', H_LOAD_SEGMENT_SET, ' ID '), &
    keyword_entry_t('LOAD_BODY_X', H_LOAD_BODY_X, ' '), &
    keyword_entry_t('LOAD_BODY_Y', H_LOAD_BODY_Y, ' '), &
    keyword_entry_t('LOAD_BODY_Z', H_LOAD_BODY_Z, ' '), &
    keyword_entry_t('LOAD_BODY_PARTS', H_LOAD_BODY_PARTS, ' '), &
    keyword_entry_t('INITIAL_VELOCITY', H_INITIAL_VELOCITY, ' '), &
    keyword_entry_t('INITIAL_VELOCITY_NODE', H_INITIAL_VELOCITY_NODE, ' '), &
    keyword_entry_t('INITIAL_VELOCITY_GENERATION', H_INITIAL_VELOCITY_GENERATION, ' '), &
    ! contact and rigid walls
    keyword_entry_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', H_CONTACT_SURFACE_TO_SURFACE, &
                    ' MORTAR ID TITLE MPP '), &
    keyword_entry_t('CONTACT_AUTOMATIC_SINGLE_SURFACE', H_CONTACT_SINGLE_SURFACE, &
                    ' MORTAR ID TITLE MPP '), &
    keyword_entry_t('CONTACT_AUTOMATIC_GENERAL', H_CONTACT_SINGLE_SURFACE, ' ID TITLE MPP '), &
    keyword_entry_t('CONTACT_AUTOMATIC_NODES_TO_SURFACE', H_CONTACT_NODES_TO_SURFACE, &
                    ' MORTAR ID TITLE MPP '), &
    keyword_entry_t('CONTACT_NODES_TO_SURFACE', H_CONTACT_NODES_TO_SURFACE, ' ID TITLE MPP '), &
    keyword_entry_t('CONTACT_TIED_SURFACE_TO_SURFACE', H_CONTACT_TIED, &
                    ' OFFSET CONSTRAINED ID TITLE MPP '), &
    keyword_entry_t('CONTACT_TIED_NODES_TO_SURFACE', H_CONTACT_TIED, &
                    ' OFFSET CONSTRAINED ID TITLE MPP '), &
    ! the tiebreak contacts: a tie that fails, then the contact (card 4: the failure)
    keyword_entry_t('CONTACT_TIEBREAK_SURFACE_TO_SURFACE', H_CONTACT_TIEBREAK, &
                    ' ID TITLE MPP '), &
    keyword_entry_t('CONTACT_TIEBREAK_NODES_TO_SURFACE', H_CONTACT_TIEBREAK, &
                    ' ID TITLE MPP '), &
    keyword_entry_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_TIEBREAK', H_CONTACT_TIEBREAK, &
                    ' MORTAR ID TITLE MPP '), &
    keyword_entry_t('CONTACT_AUTOMATIC_ONE_WAY_SURFACE_TO_SURFACE_TIEBREAK', &
                    H_CONTACT_TIEBREAK, ' MORTAR ID TITLE MPP '), &
    ! the eroding contacts: the same cards and card 4 (ISYM EROSOP IADJ)
    keyword_entry_t('CONTACT_ERODING_SURFACE_TO_SURFACE', H_CONTACT_SURFACE_TO_SURFACE, &
                    ' ID TITLE MPP '), &
    keyword_entry_t('CONTACT_ERODING_SINGLE_SURFACE', H_CONTACT_SINGLE_SURFACE, &
                    ' ID TITLE MPP '), &
    keyword_entry_t('CONTACT_ERODING_NODES_TO_SURFACE', H_CONTACT_NODES_TO_SURFACE, &
                    ' ID TITLE MPP '), &
    keyword_entry_t('CONTACT_FORCE_TRANSDUCER_PENALTY', H_CONTACT_TRANSDUCER, &
                    ' ID TITLE MPP '), &
    ! the forming contacts of DYNAFORM/eta decks: the same cards, read as the mortar contact
    keyword_entry_t('CONTACT_FORMING_ONE_WAY_SURFACE_TO_SURFACE', &
                    H_CONTACT_SURFACE_TO_SURFACE, ' ID TITLE MPP '), &
    keyword_entry_t('CONTACT_FORMING_SURFACE_TO_SURFACE', H_CONTACT_SURFACE_TO_SURFACE, &
                    ' ID TITLE MPP '), &
    keyword_entry_t('RIGIDWALL_PLANAR', H_RIGIDWALL_PLANAR, ' ID '), &
    keyword_entry_t('RIGIDWALL_GEOMETRIC_FLAT', H_RIGIDWALL_FLAT, ' MOTION ID DISPLAY '), &
    keyword_entry_t('RIGIDWALL_GEOMETRIC_PRISM', H_RIGIDWALL_PRISM, ' MOTION ID DISPLAY '), &
    keyword_entry_t('RIGIDWALL_GEOMETRIC_CYLINDER', H_RIGIDWALL_CYLINDER, &
                    ' MOTION ID DISPLAY '), &
    keyword_entry_t('RIGIDWALL_GEOMETRIC_SPHERE', H_RIGIDWALL_SPHERE, ' MOTION ID DISPLAY '), &
    keyword_entry_t('CONSTRAINED_RIGID_BODIES', H_CONSTRAINED_RIGID_BODIES, ' '), &
    keyword_entry_t('CONSTRAINED_EXTRA_NODES', H_CONSTRAINED_EXTRA_NODES, ' NODE SET '), &
    keyword_entry_t('CONSTRAINED_NODAL_RIGID_BODY', H_CONSTRAINED_NODAL_RIGID_BODY, ' '), &
    keyword_entry_t('CONSTRAINED_GLOBAL', H_CONSTRAINED_GLOBAL, ' '), &
    keyword_entry_t('CONSTRAINED_SPOTWELD', H_CONSTRAINED_SPOTWELD, ' ID '), &
    ! controls and output requests (matched before the DATABASE_ skip rule)
    keyword_entry_t('CONTROL_TIMESTEP', H_CONTROL_TIMESTEP, ' '), &
    keyword_entry_t('CONTROL_SOLUTION', H_CONTROL_SOLUTION, ' '), &
    keyword_entry_t('CONTROL_HOURGLASS', H_CONTROL_HOURGLASS, ' '), &
    keyword_entry_t('CONTROL_IMPLICIT_GENERAL', H_CONTROL_IMPLICIT_GENERAL, ' '), &
    keyword_entry_t('CONTROL_IMPLICIT_SOLUTION', H_CONTROL_IMPLICIT_SOLUTION, ' '), &
    keyword_entry_t('CONTROL_IMPLICIT_AUTO', H_CONTROL_IMPLICIT_AUTO, ' '), &
    keyword_entry_t('DATABASE_BINARY_D3PLOT', H_DATABASE_D3PLOT, ' '), &
    keyword_entry_t('DATABASE_BINARY_D3DUMP', H_DATABASE_D3DUMP, ' '), &
    keyword_entry_t('DATABASE_BINARY_RUNRSF', H_DATABASE_RUNRSF, ' '), &
    keyword_entry_t('DATABASE_GLSTAT', H_DATABASE_GLSTAT, ' '), &
    keyword_entry_t('DATABASE_RCFORC', H_DATABASE_RCFORC, ' '), &
    keyword_entry_t('DATABASE_NODOUT', H_DATABASE_NODOUT, ' '), &
    keyword_entry_t('DATABASE_HISTORY_NODE', H_HISTORY_NODE, ' '), &
    keyword_entry_t('DATABASE_HISTORY_NODE_SET', H_HISTORY_NODE_SET, ' '), &
    keyword_entry_t('MEFEM_ENRICHMENT', H_MEFEM_ENRICHMENT, ' ') ]

  !> A keyword skipped with one warning, and why skipping it is safe.
  type :: skipped_entry_t
    character(len=32) :: prefix = ''     !< keyword names starting with this are skipped
    character(len=128) :: reason = ''    !< the consequence, stated in the warning
  end type skipped_entry_t

  !> An LS-DYNA keyword whose name begins with that of a keyword mefem reads but which is
  !> another keyword (not an option of it): reported as itself, never as an option of the
  !> shorter one, and without a "did you mean".
  type :: distinct_keyword_t
    character(len=40) :: name = ''       !< the whole keyword name (options may follow)
    character(len=48) :: what = ''       !< what it is
  end type distinct_keyword_t
  integer, parameter :: N_DISTINCT = 7
  type(distinct_keyword_t), parameter :: DISTINCT(N_DISTINCT) = [ &
    distinct_keyword_t('MAT_ELASTIC_PLASTIC_THERMAL', 'material MAT_004'), &
    distinct_keyword_t('MAT_ELASTIC_PLASTIC_HYDRO', 'material MAT_010'), &
    distinct_keyword_t('MAT_ELASTIC_VISCOPLASTIC_THERMAL', 'material MAT_106'), &
    distinct_keyword_t('MAT_ELASTIC_SPRING_DISCRETE_BEAM', 'material MAT_S01'), &
    distinct_keyword_t('MAT_ELASTIC_6DOF_SPRING_DISCRETE_BEAM', 'material MAT_093'), &
    distinct_keyword_t('MAT_RIGID_DISCRETE', 'material MAT_220'), &
    distinct_keyword_t('ELEMENT_TSHELL', 'thick shell elements')]

  character(len=*), parameter :: OUTPUT_ONLY = 'output or cosmetic setting not used by mefem'

  !> Keywords skipped with one warning: output and cosmetic settings (they cannot change
  !> the answer), and settings that have no counterpart in mefem's formulation:
  !> - *CONTROL_CONTACT: global contact defaults; mefem's mortar contact takes everything it
  !>   uses from each *CONTACT card;
  !> - *CONTROL_SOLID / *CONTROL_SHELL: element options of LS-DYNA's formulations; mefem's
  !>   formulation of each part follows from its section's ELFORM;
  !> - *CONTROL_ACCURACY: objective-update and node-ordering options; mefem always uses its
  !>   own objective finite-strain update;
  !> - *CONTROL_BULK_VISCOSITY: mefem adds no bulk viscosity; only shock-dominated problems
  !>   (impact), not forming, would notice.
  integer, parameter :: N_SKIPPED = 16
  type(skipped_entry_t), parameter :: SKIPPED(N_SKIPPED) = [ &
    skipped_entry_t('DATABASE_RWFORC', 'its interval is not used: rwforc is written at the '// &
                    '*DATABASE_GLSTAT interval'), &
    skipped_entry_t('DATABASE_RBDOUT', 'its interval is not used: rbdout is written at the '// &
                    '*DATABASE_GLSTAT interval'), &
    skipped_entry_t('DATABASE_', OUTPUT_ONLY), &
    skipped_entry_t('CONTROL_OUTPUT', OUTPUT_ONLY), &
    skipped_entry_t('CONTROL_ENERGY', OUTPUT_ONLY), &
    skipped_entry_t('CONTROL_CPU', OUTPUT_ONLY), &
    skipped_entry_t('CONTROL_PARALLEL', 'no effect: ranks come from mpirun; explicit '// &
                    'results are the same bits on any rank count (CONST = 1) whatever CONST '// &
                    'says'), &
    skipped_entry_t('CONTROL_MPP_', 'no effect: mefem partitions with METIS and balances '// &
                    'the ranks of a node by work stealing'), &
    skipped_entry_t('INTERFACE_SPRINGBACK', OUTPUT_ONLY), &
    skipped_entry_t('COMMENT', OUTPUT_ONLY), &
    skipped_entry_t('KEYWORD_ID', OUTPUT_ONLY), &
    skipped_entry_t('CONTROL_CONTACT', 'global contact defaults are not used; each '// &
                    '*CONTACT card sets its own stiffness scale and friction'), &
    skipped_entry_t('CONTROL_SOLID', 'solid element options are not used; each part''s '// &
                    'formulation follows its *SECTION_SOLID ELFORM'), &
    skipped_entry_t('CONTROL_SHELL', 'shell options are not used; shells are plane-strain '// &
                    'triangles or rigid tool surfaces'), &
    skipped_entry_t('CONTROL_ACCURACY', 'accuracy options are not used; mefem always uses '// &
                    'its objective finite-strain stress update'), &
    skipped_entry_t('CONTROL_BULK_VISCOSITY', 'no bulk viscosity is applied; shock fronts '// &
                    'are not smeared (matters for impact, not for forming)') ]

contains

  !> Read the deck at path into model; returns the number of input errors found.
  subroutine read_deck(path, model, n_errors)
    character(len=*), intent(in) :: path     !< main deck file
    type(model_t), intent(inout) :: model    !< the model read
    integer, intent(out) :: n_errors         !< input errors found (0 = deck accepted)
    type(reader_t) :: rd
    logical :: ok, seen_keyword, data_reported
    integer :: n_keywords
    call deck_open(rd%deck, path, ok)
    if (.not. ok) then
      n_errors = input_error_count()
      return
    end if
    seen_keyword = .false.
    data_reported = .false.
    n_keywords = 0
    do
      call deck_next_line(rd%deck)
      if (rd%deck%kind == LINE_EOF) exit
      if (rd%deck%kind == LINE_DATA) then
        if (.not. data_reported) call input_error(location(rd%deck%file, rd%deck%line), &
            'data line outside any keyword: "'//trim(rd%deck%text(1:min(rd%deck%length, 40)))// &
            '" (is a *KEYWORD line missing above it?)')
        data_reported = .true.
        cycle
      end if
      if (rd%deck%kind /= LINE_KEYWORD) cycle
      data_reported = .false.
      n_keywords = n_keywords + 1
      call dispatch_and_note(rd, model, n_keywords == 1)
    end do
    if (n_keywords == 0) call input_error(path, &
        'the deck holds no keyword (an LS-DYNA keyword deck starts with *KEYWORD)')
    call deck_close(rd%deck)
    n_errors = input_error_count()
  end subroutine read_deck

  !> Identify the keyword on the current line and call its handler.
  subroutine dispatch(rd, model, first)
    type(reader_t), intent(inout) :: rd     !< reading state at a keyword line
    type(model_t), intent(inout) :: model   !< the model read
    logical, intent(in) :: first            !< this is the deck's first keyword
    character(len=:), allocatable :: line, name, rest, options, opt
    integer :: k, e, best, blank
    line = rd%deck%text(2:rd%deck%length)
    blank = scan(line, ' ,')
    if (blank == 0) then
      name = to_upper(line)
      rest = ''
    else
      name = to_upper(line(1:blank-1))
      rest = adjustl(line(blank+1:))
    end if
    ! format suffix: '+' long, '-' standard (attached to the name or as the next token)
    rd%long = rd%long_default
    if (len(name) > 1) then
      if (name(len(name):len(name)) == '+') then
        rd%long = .true.
        name = name(1:len(name)-1)
      else if (name(len(name):len(name)) == '-') then
        rd%long = .false.
        name = name(1:len(name)-1)
      end if
    end if
    if (len_trim(rest) > 0) then
      if (rest(1:1) == '+') rd%long = .true.
      if (rest(1:1) == '-') rd%long = .false.
    end if
    rd%keyword = '*'//name
    rd%kw_file = rd%deck%file
    rd%kw_line = rd%deck%line
    if (first .and. name /= 'KEYWORD' .and. .not. starts_with(name, 'KEYWORD_')) &
      call keyword_error(rd, &
        'the deck must begin with *KEYWORD (only comments may precede it)')
    ! another LS-DYNA keyword whose name begins with a registered one
    do e = 1, N_DISTINCT
      if (name == trim(DISTINCT(e)%name) .or. starts_with(name, trim(DISTINCT(e)%name)//'_')) &
        then
        call keyword_error(rd, 'keyword not supported by mefem (*'//trim(DISTINCT(e)%name)// &
            ', '//trim(DISTINCT(e)%what)//'); it could change the analysis, so it is not '// &
            'ignored')
        call skip_cards(rd)
        return
      end if
    end do
    ! longest registered base name that the keyword starts with
    best = 0
    do e = 1, N_ENTRIES
      if (name == trim(REGISTRY(e)%base) .or. starts_with(name, trim(REGISTRY(e)%base)//'_')) then
        if (best == 0) then
          best = e
        else if (len_trim(REGISTRY(e)%base) > len_trim(REGISTRY(best)%base)) then
          best = e
        end if
      end if
    end do
    if (best == 0) then
      call skip_or_reject(rd, name)
      return
    end if
    ! options after the base name, each accepted by the entry
    options = ' '
    rest = name(len_trim(REGISTRY(best)%base)+2:)
    do while (len(rest) > 0)
      k = index(rest, '_')
      if (k == 0) then
        opt = rest
        rest = ''
      else
        opt = rest(1:k-1)
        rest = rest(k+1:)
      end if
      if (index(REGISTRY(best)%options, ' '//opt//' ') == 0) then
        ! not a variant mefem reads: an output-only keyword is skipped, anything else an error
        if (is_skipped(name)) then
          call skip_or_reject(rd, name)
        else if (len_trim(REGISTRY(best)%options) == 0) then
          call keyword_error(rd, 'keyword not supported by mefem (*'// &
              trim(REGISTRY(best)%base)//' is, without options); it could change the '// &
              'analysis, so it is not ignored')
          call skip_cards(rd)
        else
          call keyword_error(rd, 'option _'//opt//' of *'//trim(REGISTRY(best)%base)// &
              ' is not supported (accepted:'//trim(REGISTRY(best)%options)//')')
          call skip_cards(rd)
        end if
        return
      end if
      options = options//opt//' '
    end do
    select case (REGISTRY(best)%handler)
    case (H_NODE)
      call read_node(rd, model)
    case (H_ELEMENT_SOLID)
      call read_element_solid(rd, options, model)
    case (H_ELEMENT_SHELL)
      call read_element_shell(rd, options, model)
    case (H_ELEMENT_MASS)
      call read_element_mass(rd, options, model)
    case (H_ELEMENT_MASS_PART)
      call read_element_mass_part(rd, options, model)
    case (H_PART)
      call read_part(rd, options, model)
    case (H_SECTION_SOLID)
      call read_section_solid(rd, options, model)
    case (H_SECTION_SHELL)
      call read_section_shell(rd, options, model)
    case (H_HOURGLASS)
      call read_hourglass(rd, options, model)
    case (H_KEYWORD)
      call read_keyword_card(rd, line)
    case (H_TITLE)
      call read_title(rd, model)
    case (H_PARAMETER)
      call read_parameter(rd)
    case (H_PARAMETER_EXPRESSION)
      call read_parameter_expression(rd)
    case (H_CONTROL_TERMINATION)
      call read_control_termination(rd, model)
    case (H_MAT_ELASTIC)
      call read_mat_elastic(rd, options, model)
    case (H_MAT_PIECEWISE_LINEAR)
      call read_mat_piecewise_linear(rd, options, model)
    case (H_MAT_PLASTIC_KINEMATIC)
      call read_mat_plastic_kinematic(rd, options, model)
    case (H_MAT_JOHNSON_COOK)
      call read_mat_johnson_cook(rd, options, model)
    case (H_MAT_SIMPLIFIED_JOHNSON_COOK)
      call read_mat_simplified_johnson_cook(rd, options, model)
    case (H_MAT_POWER_LAW)
      call read_mat_power_law(rd, options, model)
    case (H_MAT_MOONEY_RIVLIN)
      call read_mat_mooney_rivlin(rd, options, model)
    case (H_MAT_RIGID)
      call read_mat_rigid(rd, options, model)
    case (H_SET_NODE)
      call read_set_node(rd, options, model)
    case (H_SET_PART)
      call read_set_part(rd, options, model)
    case (H_SET_SEGMENT)
      call read_set_segment(rd, options, model)
    case (H_SET_SOLID)
      call read_set_element(rd, options, SET_SOLID, model)
    case (H_SET_SHELL)
      call read_set_element(rd, options, SET_SHELL, model)
    case (H_SPC_NODE)
      call read_boundary_spc(rd, options, .false., model)
    case (H_SPC_SET)
      call read_boundary_spc(rd, options, .true., model)
    case (H_MOTION_NODE)
      call read_prescribed_motion(rd, options, ON_NODE, model)
    case (H_MOTION_SET)
      call read_prescribed_motion(rd, options, ON_NODE_SET, model)
    case (H_MOTION_RIGID)
      call read_prescribed_motion(rd, options, ON_PART, model)
    case (H_MAT_ADD_EROSION)
      call read_mat_add_erosion(rd, options, model)
    case (H_CONSTRAINED_GLOBAL)
      call read_constrained_global(rd, model)
    case (H_DEFINE_BOX)
      call read_define_box(rd, options, model)
    case (H_DEFINE_CURVE)
      call read_define_curve(rd, options, model)
    case (H_DEFINE_CURVE_SMOOTH)
      call read_define_curve_smooth(rd, options, model)
    case (H_DEFINE_TABLE)
      call read_define_table(rd, options, model)
    case (H_DEFINE_COORDINATE_SYSTEM)
      call read_define_coordinate(rd, SYSTEM_BY_POINTS, options, model)
    case (H_DEFINE_COORDINATE_VECTOR)
      call read_define_coordinate(rd, SYSTEM_BY_VECTORS, options, model)
    case (H_DEFINE_COORDINATE_NODES)
      call read_define_coordinate(rd, SYSTEM_BY_NODES, options, model)
    case (H_DEFINE_VECTOR)
      call read_define_vector(rd, options, model)
    case (H_LOAD_NODE_POINT)
      call read_load_node(rd, .false., model)
    case (H_LOAD_NODE_SET)
      call read_load_node(rd, .true., model)
    case (H_LOAD_SEGMENT)
      call read_load_segment(rd, options, model)
    case (H_LOAD_SEGMENT_SET)
      call read_load_segment_set(rd, options, model)
    case (H_LOAD_BODY_X)
      call read_load_body(rd, 1, model)
    case (H_LOAD_BODY_Y)
      call read_load_body(rd, 2, model)
    case (H_LOAD_BODY_Z)
      call read_load_body(rd, 3, model)
    case (H_LOAD_BODY_PARTS)
      call read_load_body_parts(rd, model)
    case (H_INITIAL_VELOCITY)
      call read_initial_velocity(rd, model)
    case (H_INITIAL_VELOCITY_NODE)
      call read_initial_velocity_node(rd, model)
    case (H_INITIAL_VELOCITY_GENERATION)
      call read_initial_velocity_generation(rd, model)
    case (H_CONTACT_SURFACE_TO_SURFACE)
      if (starts_with(rd%keyword, '*CONTACT_FORMING_')) call warn(keyword_where(rd)// &
          ': read as *CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_MORTAR (mortar penalty contact; '// &
          'SURFA, the blank, is the slave side); the forming contact''s own treatment of '// &
          'shell blanks is not used (doc/keywords.md 3.10)')
      call read_contact_surface_to_surface(rd, options, model, FORM_SURFACE_TO_SURFACE)
    case (H_CONTACT_TIED)
      if (starts_with(rd%keyword, '*CONTACT_TIED_NODES')) then
        call read_contact_surface_to_surface(rd, options, model, FORM_TIED_NODES)
      else
        call read_contact_surface_to_surface(rd, options, model, FORM_TIED)
      end if
    case (H_CONTACT_TIEBREAK)
      if (starts_with(rd%keyword, '*CONTACT_TIEBREAK_NODES')) then
        call read_contact_surface_to_surface(rd, options, model, FORM_TIEBREAK_NODES)
      else if (starts_with(rd%keyword, '*CONTACT_TIEBREAK_')) then
        call read_contact_surface_to_surface(rd, options, model, FORM_TIEBREAK)
      else
        call read_contact_surface_to_surface(rd, options, model, FORM_TIEBREAK_AUTOMATIC)
      end if
    case (H_CONTACT_TRANSDUCER)
      call read_contact_surface_to_surface(rd, options, model, FORM_TRANSDUCER)
    case (H_CONTACT_SINGLE_SURFACE)
      if (starts_with(rd%keyword, '*CONTACT_AUTOMATIC_GENERAL')) call warn(keyword_where(rd)// &
          ': read as *CONTACT_AUTOMATIC_SINGLE_SURFACE (mortar penalty contact of the '// &
          'surfaces'' facets); the general contact''s edge-to-edge and beam contact is not '// &
          'computed (doc/keywords.md 3.10)')
      call read_contact_surface_to_surface(rd, options, model, FORM_SINGLE_SURFACE)
    case (H_CONTACT_NODES_TO_SURFACE)
      call warn(keyword_where(rd)//': read as *CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_MORTAR '// &
          '(mortar penalty contact; SURFA, the slave nodes, is taken as the exterior faces '// &
          'and boundary edges they span); no node-to-segment treatment (doc/keywords.md 3.10)')
      call read_contact_surface_to_surface(rd, options, model, FORM_NODES_TO_SURFACE)
    case (H_CONSTRAINED_RIGID_BODIES)
      call read_constrained_rigid_bodies(rd, model)
    case (H_CONSTRAINED_EXTRA_NODES)
      call read_constrained_extra_nodes(rd, options, model)
    case (H_CONSTRAINED_NODAL_RIGID_BODY)
      call read_constrained_nodal_rigid_body(rd, model)
    case (H_CONSTRAINED_SPOTWELD)
      call read_constrained_spotweld(rd, options, model)
    case (H_RIGIDWALL_PLANAR)
      call read_rigidwall_planar(rd, options, model)
    case (H_RIGIDWALL_FLAT)
      call read_rigidwall_geometric(rd, options, model, WALL_FLAT)
    case (H_RIGIDWALL_PRISM)
      call read_rigidwall_geometric(rd, options, model, WALL_PRISM)
    case (H_RIGIDWALL_CYLINDER)
      call read_rigidwall_geometric(rd, options, model, WALL_CYLINDER)
    case (H_RIGIDWALL_SPHERE)
      call read_rigidwall_geometric(rd, options, model, WALL_SPHERE)
    case (H_CONTROL_TIMESTEP)
      call read_control_timestep(rd, model)
    case (H_CONTROL_SOLUTION)
      call read_control_solution(rd)
    case (H_CONTROL_HOURGLASS)
      call read_control_hourglass(rd, model)
    case (H_CONTROL_IMPLICIT_GENERAL)
      call read_control_implicit_general(rd, model)
    case (H_CONTROL_IMPLICIT_SOLUTION)
      call read_control_implicit_solution(rd, model)
    case (H_CONTROL_IMPLICIT_AUTO)
      call read_control_implicit_auto(rd, model)
    case (H_DATABASE_D3PLOT)
      call read_database_binary_d3plot(rd, model)
    case (H_DATABASE_D3DUMP)
      call read_database_restart(rd, DATABASE_D3DUMP, model)
    case (H_DATABASE_RUNRSF)
      call read_database_restart(rd, DATABASE_RUNRSF, model)
    case (H_DATABASE_GLSTAT)
      call read_database_interval(rd, DATABASE_GLSTAT, model)
    case (H_DATABASE_RCFORC)
      call read_database_interval(rd, DATABASE_RCFORC, model)
    case (H_DATABASE_NODOUT)
      call read_database_interval(rd, DATABASE_NODOUT, model)
    case (H_HISTORY_NODE)
      call read_database_history_node(rd, .false., model)
    case (H_HISTORY_NODE_SET)
      call read_database_history_node(rd, .true., model)
    case (H_MEFEM_ENRICHMENT)
      call read_mefem_enrichment(rd, model)
    end select
  end subroutine dispatch

  !> dispatch, then note the id of a material whose keyword added no material (rejected: its
  !> errors are reported) or of an unsupported *MAT_ or *SECTION_ keyword, so that a part
  !> naming it is not reported again (model%rejected_material_ids, rejected_section_ids).
  subroutine dispatch_and_note(rd, model, first)
    type(reader_t), intent(inout) :: rd     !< reading state at a keyword line
    type(model_t), intent(inout) :: model   !< the model read
    logical, intent(in) :: first            !< this is the deck's first keyword
    integer :: n_materials, id
    n_materials = model%n_materials
    id = last_material_id()                 ! (forget the last keyword's)
    rejected_id = 0
    call dispatch(rd, model, first)
    id = last_material_id()
    if (starts_with(rd%keyword, '*MAT_') .and. model%n_materials == n_materials .and. &
        .not. starts_with(rd%keyword, '*MAT_ADD_EROSION')) then
      if (id == 0) id = rejected_id
      if (id /= 0) call append_id(model%rejected_material_ids, id)
    else if (starts_with(rd%keyword, '*SECTION_') .and. rejected_id /= 0) then
      call append_id(model%rejected_section_ids, rejected_id)
    end if
  contains
    !> Append one id to a list (allocated on first use).
    subroutine append_id(list, value)
      integer, allocatable, intent(inout) :: list(:)  !< the list
      integer, intent(in) :: value                    !< the id
      if (.not. allocated(list)) allocate(list(0))
      list = [list, value]
    end subroutine append_id
  end subroutine dispatch_and_note

  !> A keyword without handler: skip it with a warning if it is output or cosmetic,
  !> otherwise report it as an error (its cards are skipped either way).
  subroutine skip_or_reject(rd, name)
    type(reader_t), intent(inout) :: rd      !< reading state
    character(len=*), intent(in) :: name     !< keyword name, upper case, no '*'
    integer :: k
    do k = 1, N_SKIPPED
      if (starts_with(name, trim(SKIPPED(k)%prefix))) then
        call warn_once(name, '*'//name//' ignored ('//trim(SKIPPED(k)%reason)// &
            '), first at '//location(rd%kw_file, rd%kw_line))
        call skip_cards(rd)
        return
      end if
    end do
    call keyword_error(rd, 'keyword not supported by mefem; it could change the analysis, '// &
        'so it is not ignored (see doc/keywords.md for the supported keywords)'// &
        trim(suggestion(name)))
    call skip_cards(rd)
  end subroutine skip_or_reject

  !> "; did you mean *NAME?" when a registered keyword is within a few edits of an unknown
  !> name (a typo: *SECTON_SOLID, *BOUNDRY_SPC_SET), else blank; never for a material by its
  !> number (*MAT_004 is another material than *MAT_001, not a typo of it).
  function suggestion(name) result(text)
    character(len=*), intent(in) :: name     !< the unknown keyword name, upper case, no '*'
    character(len=80) :: text
    integer :: k, best, distance, best_distance
    text = ''
    if (len(name) > 4) then
      if (name(1:4) == 'MAT_' .and. verify(name(5:5), '0123456789') == 0) return
    end if
    best = 0
    best_distance = huge(1)
    do k = 1, N_ENTRIES
      distance = edit_distance(name, trim(REGISTRY(k)%base))
      if (distance < best_distance) then
        best = k
        best_distance = distance
      end if
    end do
    ! at most 2 edits, and fewer than a quarter of the name's letters
    if (best > 0 .and. best_distance <= min(2, len_trim(name)/4)) &
      text = '; did you mean *'//trim(REGISTRY(best)%base)//'?'
  end function suggestion

  !> Levenshtein distance of two strings (insertions, deletions, substitutions).
  pure integer function edit_distance(a, b)
    character(len=*), intent(in) :: a, b     !< the strings
    integer :: row(0:len(b)), previous(0:len(b)), i, j
    previous = [(j, j = 0, len(b))]
    do i = 1, len(a)
      row(0) = i
      do j = 1, len(b)
        row(j) = min(previous(j) + 1, row(j - 1) + 1, &
                     previous(j - 1) + merge(0, 1, a(i:i) == b(j:j)))
      end do
      previous = row
    end do
    edit_distance = previous(len(b))
  end function edit_distance

  !> True when a keyword name starts with one of the skipped (output/cosmetic) prefixes.
  logical function is_skipped(name)
    character(len=*), intent(in) :: name     !< keyword name, upper case, no '*'
    integer :: k
    is_skipped = .false.
    do k = 1, N_SKIPPED
      if (starts_with(name, trim(SKIPPED(k)%prefix))) is_skipped = .true.
    end do
  end function is_skipped

  !> Skip the data cards of the current keyword.
  subroutine skip_cards(rd)
    type(reader_t), intent(inout) :: rd   !< reading state
    type(card_t) :: card
    logical :: got, title
    integer :: n, status
    character(len=20) :: field
    ! an unsupported *MAT_ or *SECTION_ keyword: its id, the first field of its first data
    ! card (after a _TITLE card), for dispatch_and_note
    title = index(rd%keyword, '_TITLE') > 0
    n = 0
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      n = n + 1
      if (.not. (starts_with(rd%keyword, '*MAT_') .or. starts_with(rd%keyword, '*SECTION_'))) &
        cycle
      if (n /= merge(2, 1, title) .or. card%length == 0) cycle
      field = card%text(1:min(card%length, merge(20, 10, rd%long)))
      if (index(field, ',') > 0) field = field(1:index(field, ',') - 1)
      read(field, *, iostat=status) rejected_id
      if (status /= 0) rejected_id = 0
    end do
  end subroutine skip_cards

end module mefem_keyword_reader
