!> Keyword handlers for boundary conditions, curves, loads and initial conditions:
!> *BOUNDARY_SPC_NODE/_SET, *BOUNDARY_PRESCRIBED_MOTION_NODE/_SET/_RIGID, *DEFINE_CURVE,
!> *LOAD_NODE_POINT/_SET, *LOAD_SEGMENT(_SET), *LOAD_BODY_X/_Y/_Z, *LOAD_BODY_PARTS,
!> *INITIAL_VELOCITY(_NODE, _GENERATION).
!>
!> Targets (nodes, sets, parts) and curves are stored as user ids and resolved by
!> resolve_conditions. Following LS-DYNA, a scale factor SF given as 0 means 1, and a DEATH
!> time given as 0 means "never".
module mefem_read_conditions
  use mefem_kinds, only: wp
  use mefem_strings, only: itoa, rtoa
  use mefem_cards, only: reader_t, card_t, next_card, split_card, get_int, &
                         card_error, card_warning, keyword_error
  use mefem_card_layouts, only: read_layout_card, real_field, int_field, card_fields_t
  use mefem_card_helpers, only: has_option, read_title_card, read_id_card, quoted_real, &
                                skip_extra_cards, read_id_option, reject_extra_cards
  use mefem_deck_source, only: location
  use mefem_model, only: model_t, source_t, spc_t, prescribed_motion_t, curve_t, &
                         nodal_load_t, pressure_load_t, initial_velocity_t, body_load_t, ON_NODE, &
                         ON_NODE_SET, ON_PART, ON_ALL_NODES, ON_PART_SET, rigid_constraint_t, &
                         RIGID_MERGE, RIGID_EXTRA_NODES, RIGID_NODAL, box_t, global_constraint_t
  implicit none
  private

  public :: read_boundary_spc, read_prescribed_motion, read_define_curve, read_load_node, &
            read_define_curve_smooth, read_define_table, &
            read_load_segment, read_load_segment_set, read_initial_velocity, &
            read_initial_velocity_node, read_initial_velocity_generation, read_load_body, &
            read_load_body_parts, read_constrained_rigid_bodies, read_constrained_extra_nodes, &
            read_constrained_nodal_rigid_body, read_constrained_spotweld, read_define_box, &
            read_constrained_global

  integer, parameter :: W_10(8) = 10          !< standard 8 x 10 card (the _ID card of a spot weld)
  character(len=1), parameter :: AXIS_NAMES(3) = ['X', 'Y', 'Z']   !< axis names: *LOAD_BODY_ suffixes, velocity fields

contains

  !> *BOUNDARY_SPC_NODE / *BOUNDARY_SPC_SET (options ID, BIRTH_DEATH):
  !> NID|NSID CID DOFX DOFY DOFZ DOFRX DOFRY DOFRZ [/ BIRTH DEATH], repeated.
  subroutine read_boundary_spc(rd, options, on_set, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    logical, intent(in) :: on_set                !< _SET (node set) rather than _NODE
    type(model_t), intent(inout) :: model        !< model appended to
    type(card_t) :: card, card2
    type(card_fields_t) :: f
    type(spc_t) :: spc
    logical :: got, ok, birth_death
    integer :: flags(6), i, id
    character(len=80) :: heading
    character(len=5), parameter :: DOF_NAMES(6) = ['DOFX ', 'DOFY ', 'DOFZ ', 'DOFRX', &
                                                   'DOFRY', 'DOFRZ']
    call read_id_option(rd, options, id, heading, ok)
    if (.not. ok) return
    birth_death = has_option(options, 'BIRTH') .or. has_option(options, 'DEATH')
    if (birth_death .and. .not. (has_option(options, 'BIRTH') .and. &
                                 has_option(options, 'DEATH'))) then
      call keyword_error(rd, 'the option is _BIRTH_DEATH (both words)')
      call skip_extra_cards(rd)
      return
    end if
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      call read_layout_card(rd, card, 'BOUNDARY_SPC_NODE', 1, f, &
                            first_name=trim(merge('NSID', 'NID ', on_set)))
      spc = spc_t()
      spc%target_kind = merge(ON_NODE_SET, ON_NODE, on_set)
      spc%target_id = int_field(f, trim(merge('NSID', 'NID ', on_set)))
      spc%cid = int_field(f, 'CID')
      do i = 1, 6
        flags(i) = int_field(f, trim(DOF_NAMES(i)))
      end do
      spc%src = source_t(card%file, card%line)
      if (birth_death) then
        call next_card(rd, card2, got, keep_blank=.true.)
        if (.not. got) then
          call card_error(card, 'missing the card BIRTH DEATH of the _BIRTH_DEATH option')
          exit
        end if
        call read_layout_card(rd, card2, 'BOUNDARY_SPC_NODE', 2, f)
        spc%birth = real_field(f, 'BIRTH')
        spc%death = real_field(f, 'DEATH')
        if (card2%bad) cycle
        if (spc%birth >= spc%death) then
          call card_error(card2, 'field BIRTH ('//rtoa(spc%birth)//') must be before DEATH ('// &
              rtoa(spc%death)//')')
          cycle
        end if
      end if
      if (card%bad) cycle
      if (spc%target_id <= 0) then
        call card_error(card, 'field '//trim(merge('NSID', 'NID ', on_set))// &
            ' must be a positive id (got '//itoa(spc%target_id)//')')
        cycle
      end if
      if (spc%cid < 0) then
        call card_error(card, 'field CID must not be negative (got '//itoa(spc%cid)//')')
        cycle
      end if
      ok = .true.
      do i = 1, 6
        if (flags(i) /= 0 .and. flags(i) /= 1) then
          call card_error(card, 'field '//trim(DOF_NAMES(i))//' must be 0 (free) or 1 '// &
              '(fixed) (got '//itoa(flags(i))//')')
          ok = .false.
        end if
      end do
      if (.not. ok) cycle
      spc%dof = flags == 1
      call add_spc(model, spc)
    end do
  end subroutine read_boundary_spc

  !> *BOUNDARY_PRESCRIBED_MOTION_NODE/_SET/_RIGID (option ID):
  !> NID|NSID|PID DOF VAD LCID SF VID DEATH BIRTH, repeated.
  subroutine read_prescribed_motion(rd, options, target_kind, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    integer, intent(in) :: target_kind           !< ON_NODE, ON_NODE_SET or ON_PART
    type(model_t), intent(inout) :: model        !< model appended to
    type(card_t) :: card
    type(card_fields_t) :: f
    type(prescribed_motion_t) :: motion
    logical :: got, ok
    integer :: id
    character(len=80) :: heading
    character(len=:), allocatable :: target_name
    select case (target_kind)
    case (ON_NODE)
      target_name = 'NID'
    case (ON_NODE_SET)
      target_name = 'NSID'
    case default
      target_name = 'PID'
    end select
    call read_id_option(rd, options, id, heading, ok)
    if (.not. ok) return
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      call read_layout_card(rd, card, 'BOUNDARY_PRESCRIBED_MOTION_NODE', 1, f, &
                            first_name=target_name)
      motion = prescribed_motion_t()
      motion%target_kind = target_kind
      motion%target_id = int_field(f, target_name)
      motion%dof = int_field(f, 'DOF')
      motion%vad = int_field(f, 'VAD')
      motion%curve_id = int_field(f, 'LCID')
      motion%scale = real_field(f, 'SF')
      motion%vector_id = int_field(f, 'VID')
      motion%death = real_field(f, 'DEATH')
      motion%birth = real_field(f, 'BIRTH')
      motion%src = source_t(card%file, card%line)
      if (card%bad) cycle
      if (motion%target_id <= 0) then
        call card_error(card, 'field '//target_name//' must be a positive id (got '// &
            itoa(motion%target_id)//')')
      else if (.not. valid_motion_dof(card, motion, target_kind)) then
        continue
      else if (motion%vad < 0 .or. motion%vad > 4) then
        call card_error(card, 'field VAD must be 0 (velocity), 1 (acceleration) or 2 '// &
            '(displacement) (got '//itoa(motion%vad)//')')
      else if (motion%vad > 2) then
        call card_error(card, 'field VAD = '//itoa(motion%vad)//' is not supported (0 '// &
            'velocity, 1 acceleration, 2 displacement)')
      else if (motion%curve_id <= 0) then
        call card_error(card, 'field LCID must be a positive curve id (got '// &
            itoa(motion%curve_id)//')')
      else if (motion%birth >= motion%death) then
        call card_error(card, 'field BIRTH ('//rtoa(motion%birth)//') must be before DEATH ('// &
            rtoa(motion%death)//')')
      else
        call add_motion(model, motion)
      end if
    end do
  end subroutine read_prescribed_motion

  !> DOF of a prescribed motion: 1-3 translations, +-4 along vector VID, 5-7 rotations,
  !> +-8 rotation about vector VID (rigid bodies only for rotations); 9-12 and the other
  !> manual values are not supported. Reports and returns false when not valid.
  logical function valid_motion_dof(card, motion, target_kind)
    type(card_t), intent(in) :: card                  !< the card
    type(prescribed_motion_t), intent(in) :: motion   !< the motion read
    integer, intent(in) :: target_kind                !< ON_NODE, ON_NODE_SET or ON_PART
    valid_motion_dof = .false.
    select case (motion%dof)
    case (1:3)
      valid_motion_dof = .true.
    case (4, -4, 8, -8)
      if (motion%vector_id <= 0) then
        call card_error(card, 'field DOF = '//itoa(motion%dof)//' (along/about a vector) '// &
            'needs a vector id VID > 0 (got '//itoa(motion%vector_id)//')')
      else if (abs(motion%dof) == 8 .and. target_kind /= ON_PART) then
        call card_error(card, 'field DOF = '//itoa(motion%dof)//': rotations apply to '// &
            'rigid parts only (*BOUNDARY_PRESCRIBED_MOTION_RIGID); nodes of solids have no '// &
            'rotational degrees of freedom')
      else
        valid_motion_dof = .true.
      end if
    case (5:7)
      if (target_kind /= ON_PART) then
        call card_error(card, 'field DOF = '//itoa(motion%dof)//': rotations apply to '// &
            'rigid parts only (*BOUNDARY_PRESCRIBED_MOTION_RIGID); nodes of solids have no '// &
            'rotational degrees of freedom')
      else
        valid_motion_dof = .true.
      end if
    case (9:12, -11:-9)
      call card_error(card, 'field DOF = '//itoa(motion%dof)//' (rotation about offset '// &
          'axes or segment normal) is not supported (use 1-8 or -4, -8)')
    case default
      call card_error(card, 'field DOF = '//itoa(motion%dof)//' is not a valid degree of '// &
          'freedom (1-3 translation, 4/-4 along VID, 5-7 rotation, 8/-8 about VID)')
    end select
  end function valid_motion_dof

  !> *DEFINE_CURVE(_TITLE): LCID SIDR SFA SFO OFFA OFFO DATTYP / A O (2 x E20) repeated.
  !> Stored with scale and offset applied: t = SFA (A + OFFA), f = SFO (O + OFFO).
  subroutine read_define_curve(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    type(card_t) :: card, point
    type(card_fields_t) :: fields
    type(curve_t) :: curve
    logical :: got, bad
    real(wp) :: sfa, sfo, offa, offo, a, o, previous
    integer :: dattyp, previous_line, n
    real(wp), allocatable :: t(:), f(:), grown(:)
    call read_title_card(rd, options, curve%title)
    call next_card(rd, card, got)
    if (.not. got) then
      call keyword_error(rd, 'missing card 1 (LCID SIDR SFA SFO OFFA OFFO DATTYP)')
      return
    end if
    call read_layout_card(rd, card, 'DEFINE_CURVE', 1, fields)
    curve%id = int_field(fields, 'LCID')
    curve%sidr = int_field(fields, 'SIDR')
    sfa = real_field(fields, 'SFA')
    sfo = real_field(fields, 'SFO')
    offa = real_field(fields, 'OFFA')
    offo = real_field(fields, 'OFFO')
    dattyp = int_field(fields, 'DATTYP')
    curve%src = source_t(card%file, card%line)
    bad = card%bad
    if (.not. bad) then
      if (curve%id <= 0) then
        call card_error(card, 'field LCID: curve id must be positive (got '//itoa(curve%id)//')')
        bad = .true.
      else if (curve%sidr < 0 .or. curve%sidr > 2) then
        call card_error(card, 'curve '//itoa(curve%id)//': field SIDR must be 0, 1 or 2 '// &
            '(got '//itoa(curve%sidr)//')')
        bad = .true.
      else if (curve%sidr == 1) then
        ! LS-DYNA applies such a curve in dynamic relaxation only, never in the transient run
        call card_error(card, 'curve '//itoa(curve%id)//': SIDR = 1 (dynamic relaxation '// &
            'only) is not supported: mefem runs no dynamic relaxation, and LS-DYNA would not '// &
            'use this curve in the transient run; give SIDR = 0 (or 2) to apply it')
        bad = .true.
      else if (sfa < 0.0_wp) then
        call card_error(card, 'curve '//itoa(curve%id)//': field SFA must be > 0 '// &
            quoted_real(sfa))
        bad = .true.
      else if (dattyp /= 0 .and. dattyp /= 1) then
        call card_error(card, 'curve '//itoa(curve%id)//': field DATTYP = '//itoa(dattyp)// &
            ' is not supported (0 or 1: tabulated points with increasing abscissas)')
        bad = .true.
      end if
    end if
    allocate(t(16), f(16))
    n = 0
    previous = 0.0_wp
    previous_line = 0
    do
      call next_card(rd, point, got)
      if (.not. got) exit
      call read_layout_card(rd, point, 'DEFINE_CURVE', 2, fields)
      a = real_field(fields, 'A')
      o = real_field(fields, 'O')
      if (point%bad) then
        bad = .true.
        cycle
      end if
      a = sfa*(a + offa)
      o = sfo*(o + offo)
      if (n > 0 .and. a <= previous) then
        call card_error(point, 'curve '//itoa(curve%id)//': abscissa '//rtoa(a)// &
            ' of point '//itoa(n + 1)//' does not increase (previous point: '//rtoa(previous)// &
            ' at '//location(point%file, previous_line)//'); abscissas must be strictly '// &
            'increasing')
        bad = .true.
      end if
      if (n == size(t)) then
        allocate(grown(2*n))
        grown(1:n) = t
        call move_alloc(grown, t)
        allocate(grown(2*n))
        grown(1:n) = f
        call move_alloc(grown, f)
      end if
      n = n + 1
      t(n) = a
      f(n) = o
      previous = a
      previous_line = point%line
    end do
    if (n == 0 .and. .not. card%bad) then
      call card_error(card, 'curve '//itoa(curve%id)//' has no points (give A O pairs, one '// &
          'per card, after card 1)')
      bad = .true.
    end if
    if (bad) return
    curve%n = n
    curve%t = t(1:n)
    curve%f = f(1:n)
    call add_curve(model, curve)
  end subroutine read_define_curve

  !> *DEFINE_TABLE(_TITLE): TBID SFA OFFA / VALUE LCID (2 x 20 columns) repeated: one curve
  !> per value (values stored as SFA (VALUE + OFFA), strictly increasing); a blank LCID takes
  !> the curves defined right after the table, in order (LS-DYNA's original form).
  subroutine read_define_table(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    type(card_t) :: card, entry
    type(card_fields_t) :: f
    type(curve_t) :: table
    logical :: got, bad
    real(wp) :: sfa, offa, value
    integer :: lcid, n
    real(wp), allocatable :: values(:)
    integer, allocatable :: ids(:)
    call read_title_card(rd, options, table%title)
    call next_card(rd, card, got)
    if (.not. got) then
      call keyword_error(rd, 'missing card 1 (TBID SFA OFFA)')
      return
    end if
    call read_layout_card(rd, card, 'DEFINE_TABLE', 1, f)
    table%id = int_field(f, 'TBID')
    sfa = real_field(f, 'SFA')
    offa = real_field(f, 'OFFA')
    table%src = source_t(card%file, card%line)
    table%is_table = .true.
    bad = card%bad
    if (.not. bad .and. table%id <= 0) then
      call card_error(card, 'field TBID: table id must be positive (got '//itoa(table%id)//')')
      bad = .true.
    else if (.not. bad .and. sfa < 0.0_wp) then
      call card_error(card, 'table '//itoa(table%id)//': field SFA must be > 0 '// &
                      quoted_real(sfa))
      bad = .true.
    end if
    allocate(values(0), ids(0))
    n = 0
    do
      call next_card(rd, entry, got)
      if (.not. got) exit
      call read_layout_card(rd, entry, 'DEFINE_TABLE', 2, f)
      value = real_field(f, 'VALUE')
      lcid = int_field(f, 'LCID')
      if (entry%bad) then
        bad = .true.
        cycle
      end if
      value = sfa*(value + offa)
      if (n > 0) then
        if (value <= values(n)) then
          call card_error(entry, 'table '//itoa(table%id)//': value '//rtoa(value)// &
              ' does not increase (values must be strictly increasing)')
          bad = .true.
        end if
      end if
      if (lcid < 0) then
        call card_error(entry, 'table '//itoa(table%id)//': field LCID must not be negative '// &
                        '(got '//itoa(lcid)//')')
        bad = .true.
      end if
      n = n + 1
      values = [values, value]
      ids = [ids, lcid]
    end do
    if (n == 0 .and. .not. card%bad) then
      call card_error(card, 'table '//itoa(table%id)//' has no values (give VALUE and LCID, '// &
          'one per card, after card 1)')
      bad = .true.
    end if
    if (bad) return
    table%n = n
    table%t = values
    table%member_ids = ids
    table%follows = model%n_curves + 2
    call add_curve(model, table)
  end subroutine read_define_table

  !> *DEFINE_CURVE_SMOOTH(_TITLE): LCID SIDR DIST TSTART TEND TRISE V0. A velocity curve
  !> that rises from 0 at TSTART to V0 over TRISE, stays at V0 and falls back to 0 at TEND over
  !> TRISE, its area DIST: V0 = DIST/(TEND - TSTART - TRISE) when TEND is given, else
  !> TEND = TSTART + TRISE + DIST/V0. The ramps are half cosine waves, V0 (1 - cos(pi s))/2,
  !> sampled at SMOOTH_RAMP_INTERVALS intervals (the sampled curve's area is DIST exactly: the
  !> cosine terms cancel in pairs); 0 before TSTART and after TEND.
  subroutine read_define_curve_smooth(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    integer, parameter :: SMOOTH_RAMP_INTERVALS = 16
    real(wp), parameter :: PI = 3.14159265358979323846_wp
    type(card_t) :: card
    type(card_fields_t) :: f
    type(curve_t) :: curve
    logical :: got
    real(wp) :: dist, t_start, t_end, t_rise, v_max, s, span
    integer :: k, n
    character(len=:), allocatable :: who
    call read_title_card(rd, options, curve%title)
    call next_card(rd, card, got)
    if (.not. got) then
      call keyword_error(rd, 'missing card 1 (LCID SIDR DIST TSTART TEND TRISE V0)')
      return
    end if
    call read_layout_card(rd, card, 'DEFINE_CURVE_SMOOTH', 1, f)
    curve%id = int_field(f, 'LCID')
    curve%sidr = int_field(f, 'SIDR')
    dist = real_field(f, 'DIST')
    t_start = real_field(f, 'TSTART')
    t_end = real_field(f, 'TEND')
    t_rise = real_field(f, 'TRISE')
    v_max = real_field(f, 'V0')
    curve%src = source_t(card%file, card%line)
    call reject_extra_cards(rd, 'curve '//itoa(curve%id))
    if (card%bad) return
    who = 'curve '//itoa(curve%id)//': '
    if (curve%id <= 0) then
      call card_error(card, 'field LCID: curve id must be positive (got '//itoa(curve%id)//')')
      return
    else if (curve%sidr /= 0 .and. curve%sidr /= 2) then
      call card_error(card, who//'field SIDR must be 0 or 2 (got '//itoa(curve%sidr)//')')
      return
    else if (t_start < 0.0_wp .or. .not. t_rise > 0.0_wp) then
      call card_error(card, who//'fields TSTART >= 0 and TRISE > 0 are needed (got '// &
          rtoa(t_start)//', '//rtoa(t_rise)//')')
      return
    else if ((t_end /= 0.0_wp) .eqv. (v_max /= 0.0_wp)) then
      call card_error(card, who//'give exactly one of TEND and V0 (the other follows from DIST)')
      return
    end if
    if (t_end /= 0.0_wp) then
      if (t_end - t_start < 2.0_wp*t_rise) then
        call card_error(card, who//'TEND - TSTART = '//rtoa(t_end - t_start)//' must be at '// &
            'least 2 TRISE = '//rtoa(2.0_wp*t_rise)//' (a rise and a fall)')
        return
      end if
      v_max = dist/(t_end - t_start - t_rise)
    else
      t_end = t_start + t_rise + dist/v_max
      if (dist/v_max < t_rise) then
        call card_error(card, who//'DIST/V0 = '//rtoa(dist/v_max)//' must be at least TRISE '// &
            '(the curve rises and falls over TRISE each)')
        return
      end if
    end if
    span = t_end - t_start
    n = 2*SMOOTH_RAMP_INTERVALS + 6
    allocate(curve%t(n), curve%f(n))
    curve%t(1) = t_start - span                   ! zero before TSTART (flat extrapolation)
    curve%f(1) = 0.0_wp
    n = 1
    do k = 0, SMOOTH_RAMP_INTERVALS
      s = real(k, wp)/real(SMOOTH_RAMP_INTERVALS, wp)
      call add_point(t_start + s*t_rise, 0.5_wp*v_max*(1.0_wp - cos(PI*s)))
    end do
    do k = 0, SMOOTH_RAMP_INTERVALS
      s = real(k, wp)/real(SMOOTH_RAMP_INTERVALS, wp)
      call add_point(t_end - t_rise + s*t_rise, 0.5_wp*v_max*(1.0_wp + cos(PI*s)))
    end do
    call add_point(t_end + span, 0.0_wp)          ! zero after TEND
    curve%n = n
    curve%t = curve%t(1:n)
    curve%f = curve%f(1:n)
    call add_curve(model, curve)

  contains

    !> Append a point; one at the abscissa of the last (no plateau) is the same point.
    subroutine add_point(t, f)
      real(wp), intent(in) :: t, f               !< abscissa, ordinate
      if (t <= curve%t(n)) return
      n = n + 1
      curve%t(n) = t
      curve%f(n) = f
    end subroutine add_point

  end subroutine read_define_curve_smooth

  !> *LOAD_NODE_POINT / *LOAD_NODE_SET: NID|NSID DOF LCID SF CID M1 M2 M3, repeated.
  subroutine read_load_node(rd, on_set, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    logical, intent(in) :: on_set                !< _SET (node set) rather than _POINT
    type(model_t), intent(inout) :: model        !< model appended to
    type(card_t) :: card
    type(card_fields_t) :: f
    type(nodal_load_t) :: load
    logical :: got
    character(len=:), allocatable :: target_name
    target_name = trim(merge('NSID', 'NID ', on_set))
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      call read_layout_card(rd, card, 'LOAD_NODE_POINT', 1, f, first_name=target_name)
      load = nodal_load_t()
      load%target_kind = merge(ON_NODE_SET, ON_NODE, on_set)
      load%target_id = int_field(f, target_name)
      load%dof = int_field(f, 'DOF')
      load%curve_id = int_field(f, 'LCID')
      load%scale = real_field(f, 'SF')
      load%cid = int_field(f, 'CID')
      load%src = source_t(card%file, card%line)
      if (card%bad) cycle
      if (load%target_id <= 0) then
        call card_error(card, 'field '//target_name//' must be a positive id (got '// &
            itoa(load%target_id)//')')
      else if (load%dof >= 4 .and. load%dof <= 8) then
        call card_error(card, 'field DOF = '//itoa(load%dof)//' is not supported: '// &
            'follower forces and moments need rotational degrees of freedom (use 1-3)')
      else if (load%dof < 1 .or. load%dof > 3) then
        call card_error(card, 'field DOF must be 1, 2 or 3 (force in x, y, z) (got '// &
            itoa(load%dof)//')')
      else if (load%curve_id <= 0) then
        call card_error(card, 'field LCID must be a positive curve id (got '// &
            itoa(load%curve_id)//')')
      else if (load%cid < 0) then
        call card_error(card, 'field CID must not be negative (got '//itoa(load%cid)//')')
      else
        call add_nodal_load(model, load)
      end if
    end do
  end subroutine read_load_node

  !> *LOAD_SEGMENT (option ID): LCID SF AT N1 N2 N3 N4 N5, repeated (triangle: N4 = N3).
  subroutine read_load_segment(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    character(len=2), parameter :: NODE_NAMES(4) = ['N1', 'N2', 'N3', 'N4']
    type(card_t) :: card
    type(card_fields_t) :: f
    type(pressure_load_t) :: load
    logical :: got, ok
    integer :: i, n5, id
    character(len=80) :: heading
    call read_id_option(rd, options, id, heading, ok)
    if (.not. ok) return
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      call read_layout_card(rd, card, 'LOAD_SEGMENT', 1, f)
      load = pressure_load_t()
      load%curve_id = int_field(f, 'LCID')
      load%scale = real_field(f, 'SF')
      load%arrival = real_field(f, 'AT')
      do i = 1, 4
        load%node_ids(i) = int_field(f, NODE_NAMES(i))
      end do
      n5 = int_field(f, 'N5')
      load%src = source_t(card%file, card%line)
      if (card%bad) cycle
      ! 2D line segment: N1 N2 with N3 (and N4) blank or repeating N2 -> N1 N2 N2 N2
      if (load%node_ids(3) == 0 .or. load%node_ids(3) == load%node_ids(2)) then
        if (all(load%node_ids(3:4) == 0 .or. load%node_ids(3:4) == load%node_ids(2))) &
          load%node_ids(3:4) = load%node_ids(2)
      end if
      if (load%node_ids(4) == 0) load%node_ids(4) = load%node_ids(3)
      if (load%curve_id <= 0) then
        call card_error(card, 'field LCID must be a positive curve id (got '// &
            itoa(load%curve_id)//')')
      else if (any(load%node_ids <= 0)) then
        call card_error(card, 'fields N1-N4: a segment needs two (2D line), three or four '// &
            'positive node ids')
      else if (n5 /= 0) then
        call card_error(card, 'field N5: higher-order (8-node) segments are not supported')
      else
        call add_pressure_load(model, load)
      end if
    end do
  end subroutine read_load_segment

  !> *LOAD_SEGMENT_SET (option ID): SSID LCID SF AT, repeated.
  subroutine read_load_segment_set(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    type(card_t) :: card
    type(card_fields_t) :: f
    type(pressure_load_t) :: load
    logical :: got, ok
    integer :: id
    character(len=80) :: heading
    call read_id_option(rd, options, id, heading, ok)
    if (.not. ok) return
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      call read_layout_card(rd, card, 'LOAD_SEGMENT_SET', 1, f)
      load = pressure_load_t()
      load%set_id = int_field(f, 'SSID')
      load%curve_id = int_field(f, 'LCID')
      load%scale = real_field(f, 'SF')
      load%arrival = real_field(f, 'AT')
      load%src = source_t(card%file, card%line)
      if (card%bad) cycle
      if (load%set_id <= 0) then
        call card_error(card, 'field SSID must be a positive segment set id (got '// &
            itoa(load%set_id)//')')
      else if (load%curve_id <= 0) then
        call card_error(card, 'field LCID must be a positive curve id (got '// &
            itoa(load%curve_id)//')')
      else
        call add_pressure_load(model, load)
      end if
    end do
  end subroutine read_load_segment_set

  !> *LOAD_BODY_X / _Y / _Z (direction 1, 2, 3): LCID SF LCIDDR XC YC ZC CID, one card.
  !> The base acceleration SF curve(t) along the axis; LCIDDR (dynamic relaxation) is read and
  !> ignored with a warning, XC YC ZC (centre of rotational loads) are read and not used, CID
  !> must be 0. One keyword per direction (a second one is an error, not a sum).
  subroutine read_load_body(rd, direction, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    integer, intent(in) :: direction             !< 1 x, 2 y, 3 z
    type(model_t), intent(inout) :: model        !< model appended to
    type(card_t) :: card
    type(card_fields_t) :: f
    type(body_load_t) :: load
    logical :: got
    integer :: cid, k
    call next_card(rd, card, got)
    if (.not. got) then
      call keyword_error(rd, 'missing card 1 (LCID SF LCIDDR XC YC ZC CID)')
      return
    end if
    call read_layout_card(rd, card, 'LOAD_BODY_X', 1, f)        ! (one layout: X, Y, Z)
    load%direction = direction
    load%curve_id = int_field(f, 'LCID')
    load%scale = real_field(f, 'SF')
    load%dr_curve_id = int_field(f, 'LCIDDR')
    load%centre = [real_field(f, 'XC'), real_field(f, 'YC'), real_field(f, 'ZC')]
    cid = int_field(f, 'CID')
    load%src = source_t(card%file, card%line)
    call reject_extra_cards(rd, 'the body load *LOAD_BODY_'//AXIS_NAMES(direction))
    if (card%bad) return
    if (load%curve_id <= 0) then
      call card_error(card, 'field LCID must be a positive curve id (got '// &
          itoa(load%curve_id)//')')
      return
    end if
    if (cid /= 0) then
      call card_error(card, 'field CID = '//itoa(cid)//': body loads in a local coordinate '// &
          'system are not supported (use CID = 0: the global axes)')
      return
    end if
    if (load%dr_curve_id /= 0) call card_warning(card, 'field LCIDDR = '// &
        itoa(load%dr_curve_id)//' ignored: mefem runs no dynamic relaxation (the load '// &
        'follows LCID from t = 0)')
    do k = 1, model%n_body_loads
      if (model%body_loads(k)%direction /= direction) cycle
      call card_error(card, '*LOAD_BODY_'//AXIS_NAMES(direction)//' is given twice (first '// &
          'at '//location(model%body_loads(k)%src%file, model%body_loads(k)%src%line)// &
          '); give one body load per direction')
      return
    end do
    call add_body_load(model, load)
  end subroutine read_load_body

  !> *LOAD_BODY_PARTS: PSID, one card: the body loads act on the parts of part set PSID only.
  subroutine read_load_body_parts(rd, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    type(model_t), intent(inout) :: model        !< model set
    type(card_t) :: card
    type(card_fields_t) :: f
    logical :: got
    integer :: psid
    call next_card(rd, card, got)
    if (.not. got) then
      call keyword_error(rd, 'missing card 1 (PSID)')
      return
    end if
    call read_layout_card(rd, card, 'LOAD_BODY_PARTS', 1, f)
    psid = int_field(f, 'PSID')
    call reject_extra_cards(rd, 'the body load parts *LOAD_BODY_PARTS')
    if (card%bad) return
    if (psid <= 0) then
      call card_error(card, 'field PSID must be a positive part set id (got '//itoa(psid)//')')
    else if (model%body_part_set_id > 0) then
      call card_error(card, '*LOAD_BODY_PARTS is given twice (first at '// &
          location(model%body_part_src%file, model%body_part_src%line)//')')
    else
      model%body_part_set_id = psid
      model%body_part_src = source_t(card%file, card%line)
    end if
  end subroutine read_load_body_parts

  !> *INITIAL_VELOCITY: NSID NSIDEX BOXID IRIGID ICID / VX VY VZ VXR VYR VZR /
  !> [NSIDEX > 0: VXE VYE VZE VXRE VYRE VZRE], repeated. NSID = 0: all nodes.
  subroutine read_initial_velocity(rd, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    type(model_t), intent(inout) :: model        !< model appended to
    character(len=*), parameter :: KEY = 'INITIAL_VELOCITY'
    type(card_t) :: card, card2, card3
    type(card_fields_t) :: f
    type(initial_velocity_t) :: iv
    logical :: got, bad
    integer :: icid, k
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      call read_layout_card(rd, card, KEY, 1, f)
      iv = initial_velocity_t()
      iv%target_id = int_field(f, 'NSID')
      iv%exempt_set_id = int_field(f, 'NSIDEX')
      iv%box_id = int_field(f, 'BOXID')
      icid = int_field(f, 'ICID')
      iv%src = source_t(card%file, card%line)
      bad = card%bad
      call next_card(rd, card2, got, keep_blank=.true.)
      if (.not. got) then
        call card_error(card, 'missing card 2 (VX VY VZ VXR VYR VZR)')
        exit
      end if
      call read_layout_card(rd, card2, KEY, 2, f)
      do k = 1, 3
        iv%v(k) = real_field(f, 'V'//AXIS_NAMES(k))
        iv%omega_vector(k) = real_field(f, 'V'//AXIS_NAMES(k)//'R')
      end do
      bad = bad .or. card2%bad
      if (iv%exempt_set_id > 0) then
        call next_card(rd, card3, got, keep_blank=.true.)
        if (.not. got) then
          call card_error(card, 'missing card 3 (VXE VYE VZE ...) of the exempted nodes NSIDEX')
          exit
        end if
        call read_layout_card(rd, card3, KEY, 3, f)
        do k = 1, 3
          iv%v_exempt(k) = real_field(f, 'V'//AXIS_NAMES(k)//'E')
        end do
        bad = bad .or. card3%bad
      end if
      if (bad) cycle
      iv%target_kind = merge(ON_NODE_SET, ON_ALL_NODES, iv%target_id /= 0)
      if (iv%target_id < 0 .or. iv%exempt_set_id < 0 .or. iv%box_id < 0) then
        call card_error(card, 'fields NSID/NSIDEX/BOXID must not be negative')
      else if (icid < 0) then
        call card_error(card, 'field ICID must not be negative (got '//itoa(icid)//')')
      else
        iv%system_id = icid
        call add_initial_velocity(model, iv)
      end if
    end do
  end subroutine read_initial_velocity

  !> *INITIAL_VELOCITY_NODE: NID VX VY VZ VXR VYR VZR ICID, repeated.
  subroutine read_initial_velocity_node(rd, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    type(model_t), intent(inout) :: model        !< model appended to
    type(card_t) :: card
    type(card_fields_t) :: f
    type(initial_velocity_t) :: iv
    logical :: got
    integer :: k, icid
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      call read_layout_card(rd, card, 'INITIAL_VELOCITY_NODE', 1, f)
      iv = initial_velocity_t()
      iv%target_kind = ON_NODE
      iv%target_id = int_field(f, 'NID')
      do k = 1, 3
        iv%v(k) = real_field(f, 'V'//AXIS_NAMES(k))
        iv%omega_vector(k) = real_field(f, 'V'//AXIS_NAMES(k)//'R')
      end do
      icid = int_field(f, 'ICID')
      iv%src = source_t(card%file, card%line)
      if (card%bad) cycle
      if (iv%target_id <= 0) then
        call card_error(card, 'field NID must be a positive node id (got '// &
            itoa(iv%target_id)//')')
      else if (icid < 0) then
        call card_error(card, 'field ICID must not be negative (got '//itoa(icid)//')')
      else
        iv%system_id = icid
        call add_initial_velocity(model, iv)
      end if
    end do
  end subroutine read_initial_velocity_node

  !> *INITIAL_VELOCITY_GENERATION: ID STYP OMEGA VX VY VZ IVATN ICID /
  !> XC YC ZC NX NY NZ PHASE IRIGID, repeated. STYP 1 part set, 2 part, 3 node set.
  subroutine read_initial_velocity_generation(rd, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    type(model_t), intent(inout) :: model        !< model appended to
    character(len=*), parameter :: KEY = 'INITIAL_VELOCITY_GENERATION'
    type(card_t) :: card, card2
    type(card_fields_t) :: f
    type(initial_velocity_t) :: iv
    logical :: got
    integer :: styp, icid, phase, k
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      call read_layout_card(rd, card, KEY, 1, f)           ! (IVATN not used)
      iv = initial_velocity_t()
      iv%generation = .true.
      iv%target_id = int_field(f, 'ID')
      styp = int_field(f, 'STYP')
      iv%omega = real_field(f, 'OMEGA')
      do k = 1, 3
        iv%v(k) = real_field(f, 'V'//AXIS_NAMES(k))
      end do
      icid = int_field(f, 'ICID')
      iv%src = source_t(card%file, card%line)
      call next_card(rd, card2, got, keep_blank=.true.)
      if (.not. got) then
        call card_error(card, 'missing card 2 (XC YC ZC NX NY NZ PHASE IRIGID)')
        exit
      end if
      call read_layout_card(rd, card2, KEY, 2, f)          ! (IRIGID not used)
      do k = 1, 3
        iv%center(k) = real_field(f, AXIS_NAMES(k)//'C')
        iv%axis(k) = real_field(f, 'N'//AXIS_NAMES(k))
      end do
      phase = int_field(f, 'PHASE')
      if (card%bad .or. card2%bad) cycle
      select case (styp)
      case (1)
        iv%target_kind = ON_PART_SET
      case (2)
        iv%target_kind = ON_PART
      case (3)
        iv%target_kind = ON_NODE_SET
      case default
        call card_error(card, 'field STYP must be 1 (part set), 2 (part) or 3 (node set) '// &
            '(got '//itoa(styp)//')')
        cycle
      end select
      if (iv%target_id <= 0) then
        call card_error(card, 'field ID must be a positive set or part id (got '// &
            itoa(iv%target_id)//')')
      else if (icid < 0) then
        call card_error(card, 'field ICID must not be negative (got '//itoa(icid)//')')
      else if (iv%omega /= 0.0_wp .and. norm2(iv%axis) == 0.0_wp) then
        call card_error(card2, 'fields NX NY NZ: the rotation axis is zero but OMEGA = '// &
            rtoa(iv%omega)//' is given')
      else if (phase /= 0 .and. phase /= 1) then
        call card_error(card2, 'field PHASE must be 0 or 1 (got '//itoa(phase)//')')
      else
        if (norm2(iv%axis) > 0.0_wp) iv%axis = iv%axis/norm2(iv%axis)
        iv%system_id = icid
        call add_initial_velocity(model, iv)
      end if
    end do
  end subroutine read_initial_velocity_generation

  !> Append an SPC.
  subroutine add_spc(model, item)
    type(model_t), intent(inout) :: model      !< model appended to
    type(spc_t), intent(in) :: item            !< the record
    type(spc_t), allocatable :: grown(:)
    if (.not. allocated(model%spcs)) allocate(model%spcs(0))
    if (model%n_spcs == size(model%spcs)) then
      allocate(grown(max(8, 2*model%n_spcs)))
      grown(1:model%n_spcs) = model%spcs(1:model%n_spcs)
      call move_alloc(grown, model%spcs)
    end if
    model%n_spcs = model%n_spcs + 1
    model%spcs(model%n_spcs) = item
  end subroutine add_spc

  !> *CONSTRAINED_RIGID_BODIES: PIDL PIDC IFLAG, repeated: the rigid part PIDC joins the rigid
  !> body of PIDL (IFLAG read, not used: the merged body's mass and inertia come from both).
  subroutine read_constrained_rigid_bodies(rd, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    type(model_t), intent(inout) :: model        !< model appended to
    type(card_t) :: card
    type(card_fields_t) :: f
    type(rigid_constraint_t) :: item
    logical :: got
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      call read_layout_card(rd, card, 'CONSTRAINED_RIGID_BODIES', 1, f)    ! (IFLAG not used)
      item = rigid_constraint_t(kind=RIGID_MERGE, target_kind=ON_PART)
      item%lead_id = int_field(f, 'PIDL')
      item%target_id = int_field(f, 'PIDC')
      item%src = source_t(card%file, card%line)
      if (card%bad) cycle
      if (item%lead_id == item%target_id) then
        call card_error(card, 'PIDL and PIDC are the same part ('//itoa(item%lead_id)//')')
        cycle
      end if
      call add_rigid_constraint(model, item)
    end do
  end subroutine read_constrained_rigid_bodies

  !> *CONSTRAINED_EXTRA_NODES_NODE (PID NID) / _SET (PID NSID), repeated: the nodes move with
  !> the rigid body of part PID (their lumped masses join it).
  subroutine read_constrained_extra_nodes(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options (NODE or SET)
    type(model_t), intent(inout) :: model        !< model appended to
    type(card_t) :: card
    type(card_fields_t) :: f
    type(rigid_constraint_t) :: item
    logical :: got, by_set
    by_set = has_option(options, 'SET')
    if (.not. (by_set .or. has_option(options, 'NODE'))) then
      call keyword_error(rd, 'give _NODE or _SET (*CONSTRAINED_EXTRA_NODES_NODE or _SET)')
      do                                       ! (its cards skipped)
        call next_card(rd, card, got)
        if (.not. got) return
      end do
    end if
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      call read_layout_card(rd, card, 'CONSTRAINED_EXTRA_NODES_NODE', 1, f, &
                            form_name=[character(len=4) :: 'NID', merge('NSID', 'NID ', by_set)])
      item = rigid_constraint_t(kind=RIGID_EXTRA_NODES, &
                                target_kind=merge(ON_NODE_SET, ON_NODE, by_set))
      item%lead_id = int_field(f, 'PID')
      item%target_id = int_field(f, trim(merge('NSID', 'NID ', by_set)))
      item%src = source_t(card%file, card%line)
      if (card%bad) cycle
      call add_rigid_constraint(model, item)
    end do
  end subroutine read_constrained_extra_nodes

  !> *CONSTRAINED_NODAL_RIGID_BODY: cards PID CID NSID PNODE IPRT DRFLAG RRFLAG, one rigid body
  !> of the nodes of NSID each (PID names it in messages and rbdout). CID, DRFLAG and RRFLAG
  !> (local systems, released degrees of freedom) are not supported; PNODE is not used.
  subroutine read_constrained_nodal_rigid_body(rd, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    type(model_t), intent(inout) :: model        !< model appended to
    type(card_t) :: card
    type(card_fields_t) :: f
    type(rigid_constraint_t) :: item
    logical :: got
    integer :: cid, pnode, drflag, rrflag
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      call read_layout_card(rd, card, 'CONSTRAINED_NODAL_RIGID_BODY', 1, f)   ! (IPRT not used)
      item = rigid_constraint_t(kind=RIGID_NODAL, target_kind=ON_NODE_SET)
      item%lead_id = int_field(f, 'PID')
      cid = int_field(f, 'CID')
      item%target_id = int_field(f, 'NSID')
      pnode = int_field(f, 'PNODE')
      drflag = int_field(f, 'DRFLAG')
      rrflag = int_field(f, 'RRFLAG')
      item%src = source_t(card%file, card%line)
      if (card%bad) cycle
      if (cid /= 0) then
        call card_error(card, 'field CID = '//itoa(cid)//': local coordinate systems are not '// &
            'supported (the body moves in the global axes)')
      else if (drflag /= 0 .or. rrflag /= 0) then
        call card_error(card, 'fields DRFLAG/RRFLAG: released degrees of freedom are not '// &
            'supported (the nodes move as one rigid body)')
      else
        if (pnode /= 0) call card_warning(card, 'PNODE ignored: the body''s centre of mass '// &
            'comes from its nodes'' masses')
        call add_rigid_constraint(model, item)
      end if
    end do
  end subroutine read_constrained_nodal_rigid_body

  !> *CONSTRAINED_SPOTWELD (option ID: an ID card first): cards N1 N2 SN SS N M TF EP, a rigid
  !> link of the two nodes (a rigid body of both; LS-DYNA's massless rigid spot weld). The
  !> weld does not fail: SN, SS, EP and TF are read, with a warning when they ask for failure.
  subroutine read_constrained_spotweld(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options (ID)
    type(model_t), intent(inout) :: model        !< model appended to
    type(card_t) :: card
    type(card_fields_t) :: f
    type(rigid_constraint_t) :: item
    logical :: got, ok
    integer :: id
    real(wp) :: sn, ss, tf, ep
    character(len=80) :: heading
    id = 0
    if (has_option(options, 'ID')) then
      call next_card(rd, card, got)
      if (.not. got) then
        call keyword_error(rd, 'missing the ID card (SWID)')
        return
      end if
      call split_card(rd, card, W_10)
      call get_int(card, 1, 'SWID', id)
      heading = ''
    end if
    ok = .true.
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      call read_layout_card(rd, card, 'CONSTRAINED_SPOTWELD', 1, f)    ! (N, M not used)
      item = rigid_constraint_t(kind=RIGID_NODAL, target_kind=ON_NODE, lead_id=id)
      item%target_id = int_field(f, 'N1')
      item%second_id = int_field(f, 'N2')
      sn = real_field(f, 'SN')
      ss = real_field(f, 'SS')
      tf = real_field(f, 'TF')
      ep = real_field(f, 'EP')
      item%src = source_t(card%file, card%line)
      if (card%bad) cycle
      if (item%target_id == item%second_id) then
        call card_error(card, 'N1 and N2 are the same node ('//itoa(item%target_id)//')')
        cycle
      end if
      if (sn > 0.0_wp .or. ss > 0.0_wp .or. tf < 1.0e20_wp .or. ep < 1.0e20_wp) &
        call card_warning(card, 'SN, SS, TF, EP ignored: the spot weld does not fail')
      call add_rigid_constraint(model, item)
    end do
  end subroutine read_constrained_spotweld

  !> Append a rigid-body constraint.
  subroutine add_rigid_constraint(model, item)
    type(model_t), intent(inout) :: model            !< model appended to
    type(rigid_constraint_t), intent(in) :: item     !< the record
    type(rigid_constraint_t), allocatable :: grown(:)
    if (.not. allocated(model%rigid_constraints)) allocate(model%rigid_constraints(0))
    if (model%n_rigid_constraints == size(model%rigid_constraints)) then
      allocate(grown(max(4, 2*model%n_rigid_constraints)))
      grown(1:model%n_rigid_constraints) = model%rigid_constraints(1:model%n_rigid_constraints)
      call move_alloc(grown, model%rigid_constraints)
    end if
    model%n_rigid_constraints = model%n_rigid_constraints + 1
    model%rigid_constraints(model%n_rigid_constraints) = item
  end subroutine add_rigid_constraint

  !> Append a prescribed motion.
  subroutine add_motion(model, item)
    type(model_t), intent(inout) :: model            !< model appended to
    type(prescribed_motion_t), intent(in) :: item    !< the record
    type(prescribed_motion_t), allocatable :: grown(:)
    if (.not. allocated(model%motions)) allocate(model%motions(0))
    if (model%n_motions == size(model%motions)) then
      allocate(grown(max(8, 2*model%n_motions)))
      grown(1:model%n_motions) = model%motions(1:model%n_motions)
      call move_alloc(grown, model%motions)
    end if
    model%n_motions = model%n_motions + 1
    model%motions(model%n_motions) = item
  end subroutine add_motion

  !> Append a curve.
  subroutine add_curve(model, item)
    type(model_t), intent(inout) :: model      !< model appended to
    type(curve_t), intent(in) :: item          !< the record
    type(curve_t), allocatable :: grown(:)
    if (.not. allocated(model%curves)) allocate(model%curves(0))
    if (model%n_curves == size(model%curves)) then
      allocate(grown(max(8, 2*model%n_curves)))
      grown(1:model%n_curves) = model%curves(1:model%n_curves)
      call move_alloc(grown, model%curves)
    end if
    model%n_curves = model%n_curves + 1
    model%curves(model%n_curves) = item
  end subroutine add_curve

  !> Append a nodal load.
  subroutine add_nodal_load(model, item)
    type(model_t), intent(inout) :: model      !< model appended to
    type(nodal_load_t), intent(in) :: item     !< the record
    type(nodal_load_t), allocatable :: grown(:)
    if (.not. allocated(model%nodal_loads)) allocate(model%nodal_loads(0))
    if (model%n_nodal_loads == size(model%nodal_loads)) then
      allocate(grown(max(8, 2*model%n_nodal_loads)))
      grown(1:model%n_nodal_loads) = model%nodal_loads(1:model%n_nodal_loads)
      call move_alloc(grown, model%nodal_loads)
    end if
    model%n_nodal_loads = model%n_nodal_loads + 1
    model%nodal_loads(model%n_nodal_loads) = item
  end subroutine add_nodal_load

  !> Append a pressure load.
  subroutine add_pressure_load(model, item)
    type(model_t), intent(inout) :: model         !< model appended to
    type(pressure_load_t), intent(in) :: item     !< the record
    type(pressure_load_t), allocatable :: grown(:)
    if (.not. allocated(model%pressure_loads)) allocate(model%pressure_loads(0))
    if (model%n_pressure_loads == size(model%pressure_loads)) then
      allocate(grown(max(8, 2*model%n_pressure_loads)))
      grown(1:model%n_pressure_loads) = model%pressure_loads(1:model%n_pressure_loads)
      call move_alloc(grown, model%pressure_loads)
    end if
    model%n_pressure_loads = model%n_pressure_loads + 1
    model%pressure_loads(model%n_pressure_loads) = item
  end subroutine add_pressure_load

  !> Append a body load.
  subroutine add_body_load(model, item)
    type(model_t), intent(inout) :: model         !< model appended to
    type(body_load_t), intent(in) :: item         !< the record
    type(body_load_t), allocatable :: grown(:)
    if (.not. allocated(model%body_loads)) allocate(model%body_loads(0))
    if (model%n_body_loads == size(model%body_loads)) then
      allocate(grown(max(3, 2*model%n_body_loads)))
      grown(1:model%n_body_loads) = model%body_loads(1:model%n_body_loads)
      call move_alloc(grown, model%body_loads)
    end if
    model%n_body_loads = model%n_body_loads + 1
    model%body_loads(model%n_body_loads) = item
  end subroutine add_body_load

  !> *CONSTRAINED_GLOBAL: TC RC DIR X Y Z TOL, repeated: the nodes on the plane through (X, Y,
  !> Z) normal to axis DIR (1 x, 2 y, 3 z), within TOL, are held as TC says (a *NODE TC code);
  !> RC (rotations) must be 0: the nodes of solids have no rotations.
  subroutine read_constrained_global(rd, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    type(model_t), intent(inout) :: model        !< model appended to
    type(card_t) :: card
    type(card_fields_t) :: f
    type(global_constraint_t) :: gc
    type(global_constraint_t), allocatable :: grown(:)
    logical :: got
    integer :: rc
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      call read_layout_card(rd, card, 'CONSTRAINED_GLOBAL', 1, f)
      gc = global_constraint_t()
      gc%tc = int_field(f, 'TC')
      rc = int_field(f, 'RC')
      gc%direction = int_field(f, 'DIR')
      gc%point = [real_field(f, 'X'), real_field(f, 'Y'), real_field(f, 'Z')]
      gc%tolerance = real_field(f, 'TOL')
      gc%src = source_t(card%file, card%line)
      if (card%bad) cycle
      if (gc%tc < 0 .or. gc%tc > 7) then
        call card_error(card, 'field TC = '//itoa(gc%tc)//' must be 0-7 (1 x, 2 y, 3 z, 4 xy, '// &
                        '5 yz, 6 zx, 7 all)')
      else if (rc /= 0) then
        call card_error(card, 'field RC = '//itoa(rc)//': rotational constraints are not '// &
                        'supported (the nodes of solids have no rotations; RC must be 0)')
      else if (gc%direction < 1 .or. gc%direction > 3) then
        call card_error(card, 'field DIR = '//itoa(gc%direction)//' must be 1 (x), 2 (y) or 3 (z)')
      else if (gc%tolerance < 0.0_wp) then
        call card_error(card, 'field TOL must not be negative (got '//rtoa(gc%tolerance)//')')
      else
        if (.not. allocated(model%global_constraints)) allocate(model%global_constraints(0))
        if (model%n_global_constraints == size(model%global_constraints)) then
          allocate(grown(max(4, 2*model%n_global_constraints)))
          grown(1:model%n_global_constraints) = &
              model%global_constraints(1:model%n_global_constraints)
          call move_alloc(grown, model%global_constraints)
        end if
        model%n_global_constraints = model%n_global_constraints + 1
        model%global_constraints(model%n_global_constraints) = gc
      end if
    end do
  end subroutine read_constrained_global

  !> *DEFINE_BOX (_TITLE): BOXID XMN XMX YMN YMX ZMN ZMX, repeated: axis-aligned boxes of the
  !> reference configuration (a node inside one: faces included).
  subroutine read_define_box(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    character(len=2), parameter :: AXIS(3) = ['X ', 'Y ', 'Z ']
    type(card_t) :: card
    type(card_fields_t) :: f
    type(box_t) :: box
    type(box_t), allocatable :: grown(:)
    character(len=80) :: title
    logical :: got
    integer :: k, nread
    call read_title_card(rd, options, title)
    nread = 0
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      nread = nread + 1
      call read_layout_card(rd, card, 'DEFINE_BOX', 1, f)
      box = box_t()
      box%id = int_field(f, 'BOXID')
      do k = 1, 3
        box%low(k) = real_field(f, trim(AXIS(k))//'MN')
        box%high(k) = real_field(f, trim(AXIS(k))//'MX')
      end do
      box%src = source_t(card%file, card%line)
      if (card%bad) cycle
      if (box%id <= 0) then
        call card_error(card, 'field BOXID: box id must be positive (got '//itoa(box%id)//')')
        cycle
      end if
      if (any(box%low > box%high)) then
        k = findloc(box%low > box%high, .true., dim=1)
        call card_error(card, 'box '//itoa(box%id)//': '//trim(AXIS(k))//'MN = '// &
            rtoa(box%low(k))//' is above '//trim(AXIS(k))//'MX = '//rtoa(box%high(k)))
        cycle
      end if
      if (.not. allocated(model%boxes)) allocate(model%boxes(0))
      if (model%n_boxes == size(model%boxes)) then
        allocate(grown(max(8, 2*model%n_boxes)))
        grown(1:model%n_boxes) = model%boxes(1:model%n_boxes)
        call move_alloc(grown, model%boxes)
      end if
      model%n_boxes = model%n_boxes + 1
      model%boxes(model%n_boxes) = box
    end do
    if (nread == 0) call keyword_error(rd, 'missing card 1 (BOXID XMN XMX YMN YMX ZMN ZMX)')
  end subroutine read_define_box

  !> Append an initial velocity.
  subroutine add_initial_velocity(model, item)
    type(model_t), intent(inout) :: model            !< model appended to
    type(initial_velocity_t), intent(in) :: item     !< the record
    type(initial_velocity_t), allocatable :: grown(:)
    integer :: n
    n = model%n_initial_velocities
    if (.not. allocated(model%initial_velocities)) allocate(model%initial_velocities(0))
    if (n == size(model%initial_velocities)) then
      allocate(grown(max(8, 2*n)))
      grown(1:n) = model%initial_velocities(1:n)
      call move_alloc(grown, model%initial_velocities)
    end if
    model%n_initial_velocities = n + 1
    model%initial_velocities(n + 1) = item
  end subroutine add_initial_velocity

end module mefem_read_conditions
