!> Keyword handlers for the mesh: *NODE, *ELEMENT_SOLID, *ELEMENT_SHELL, *ELEMENT_MASS,
!> *ELEMENT_MASS_PART, *PART, *SECTION_SOLID, *SECTION_SHELL, *HOURGLASS. Every handler reads all data cards of one keyword
!> occurrence and appends to the model; ids are resolved later (model_resolve).
module mefem_read_mesh
  use mefem_kinds, only: wp
  use mefem_strings, only: itoa, rtoa
  use mefem_cards, only: LONG_WIDTH, reader_t, card_t, next_card, split_card, get_int, get_real, &
                         card_error, keyword_error
  use mefem_card_layouts, only: read_layout_card, real_field, int_field, card_fields_t
  use mefem_model, only: model_t, nodes_t, elements_t, part_t, section_t, source_t, &
                         hourglass_t, added_mass_t, ELEM_SOLID, ELEM_SHELL, SECTION_SOLID, &
                         SECTION_SHELL, ON_NODE, ON_NODE_SET, ON_PART, ON_PART_SET
  implicit none
  private

  public :: read_node, read_element_solid, read_element_shell, read_part, read_section_solid, &
            read_section_shell, read_hourglass, has_option, read_element_mass, &
            read_element_mass_part

  integer, parameter :: W_NODE(6) = [8, 16, 16, 16, 8, 8]    !< *NODE field widths
  integer, parameter :: W_I8(10) = 8                          !< element cards: I8 fields
  !> largest |coordinate| accepted: volumes (cubes of coordinate differences) stay far from
  !> overflow (1e308), and no unit system puts a real part beyond 1e30 of its length unit
  real(wp), parameter :: COORDINATE_LIMIT = 1.0e30_wp
  !> Names of the node fields N1..N10 (constants: building them per card costs more than
  !> reading the card; the trailing blank is dropped in messages)
  character(len=3), parameter :: NODE_FIELD(10) = [character(len=3) :: 'N1', 'N2', 'N3', &
      'N4', 'N5', 'N6', 'N7', 'N8', 'N9', 'N10']

contains

  !> True when the keyword's option list holds option (e.g. 'TITLE').
  pure logical function has_option(options, option)
    character(len=*), intent(in) :: options   !< options as ' OPT1 OPT2 '
    character(len=*), intent(in) :: option    !< the option looked for
    has_option = index(options, ' '//option//' ') > 0
  end function has_option

  !> *NODE: NID X Y Z TC RC, repeated.
  subroutine read_node(rd, model)
    type(reader_t), intent(inout) :: rd   !< reading state
    type(model_t), intent(inout) :: model !< model appended to
    type(card_t) :: card
    logical :: got
    integer :: nid, tc, rc, k
    real(wp) :: x(3)
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      call split_card(rd, card, W_NODE)
      call get_int(card, 1, 'NID', nid, required=.true.)
      call get_real(card, 2, 'X', x(1))
      call get_real(card, 3, 'Y', x(2))
      call get_real(card, 4, 'Z', x(3))
      call get_int(card, 5, 'TC', tc)
      call get_int(card, 6, 'RC', rc)
      if (.not. card%bad .and. nid <= 0) then
        call card_error(card, 'field NID: node id must be positive (got '//itoa(nid)//')')
        card%bad = .true.
      end if
      if (.not. card%bad .and. (tc < 0 .or. tc > 7 .or. rc < 0 .or. rc > 7)) then
        call card_error(card, 'fields TC/RC: constraint codes must be 0 to 7')
        card%bad = .true.
      end if
      if (.not. card%bad .and. any(abs(x) > COORDINATE_LIMIT)) then
        call card_error(card, 'fields X/Y/Z: coordinate '//rtoa(x(maxloc(abs(x), 1)))// &
            ' is beyond '//rtoa(COORDINATE_LIMIT)//' in magnitude (element volumes would '// &
            'overflow); check the units')
        card%bad = .true.
      end if
      if (card%bad) cycle
      call grow_nodes(model%nodes)
      k = model%nodes%n + 1
      model%nodes%n = k
      model%nodes%id(k) = nid
      model%nodes%x(:, k) = x
      model%nodes%tc(k) = tc
      model%nodes%rc(k) = rc
      model%nodes%src(k) = source_t(card%file, card%line)
    end do
  end subroutine read_node

  !> *ELEMENT_SOLID in either layout: EID PID N1..N8 on one line (legacy), or EID PID on
  !> one line and N1..N10 on the next. Tets may repeat N4 or give only four nodes.
  subroutine read_element_solid(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    type(card_t) :: card, nodes_card
    logical :: got, one_line
    integer :: eid, pid, nodes(10), i, nfield
    if (len_trim(options) > 0) then
      call keyword_error(rd, 'options "'//trim(adjustl(options))//'" are not supported')
    end if
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      ! layout: text beyond the 16 columns of EID/PID (or more than two entries) = one line
      if (card%free) then
        nfield = count_commas(card%text(1:card%length)) + 1
        one_line = nfield > 2
      else
        one_line = len_trim(card%text(1:card%length)) > 2*merge(LONG_WIDTH, 8, rd%long)
      end if
      call split_card(rd, card, W_I8)
      call get_int(card, 1, 'EID', eid, required=.true.)
      call get_int(card, 2, 'PID', pid, required=.true.)
      nodes = 0
      if (one_line) then
        do i = 1, 8
          call get_int(card, 2 + i, NODE_FIELD(i), nodes(i))
        end do
      else
        call next_card(rd, nodes_card, got)
        if (.not. got) then
          call card_error(card, 'element '//itoa(eid)//': missing the card of nodes N1-N8')
          exit
        end if
        call split_card(rd, nodes_card, W_I8)
        do i = 1, 10
          call get_int(nodes_card, i, NODE_FIELD(i), nodes(i))
        end do
        if (nodes_card%bad) card%bad = .true.
        if (any(nodes(9:10) /= 0)) then
          call card_error(nodes_card, 'element '//itoa(eid)// &
              ': nodes N9/N10 given; 10-node tetrahedra are not supported')
          card%bad = .true.
        end if
      end if
      ! missing N5..N8 of a tet written with four nodes repeat N4
      if (all(nodes(5:8) == 0) .and. nodes(4) /= 0) nodes(5:8) = nodes(4)
      call add_element(model%elements, eid, pid, ELEM_SOLID, nodes(1:8), card)
    end do
  end subroutine read_element_solid

  !> *ELEMENT_SHELL: EID PID N1 N2 N3 N4 (triangles: N4 = N3 or blank).
  subroutine read_element_shell(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    type(card_t) :: card
    logical :: got
    integer :: eid, pid, nodes(8), i
    if (len_trim(options) > 0) then
      call keyword_error(rd, 'options "'//trim(adjustl(options))//'" are not supported')
    end if
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      call split_card(rd, card, W_I8)
      call get_int(card, 1, 'EID', eid, required=.true.)
      call get_int(card, 2, 'PID', pid, required=.true.)
      nodes = 0
      do i = 1, 8
        call get_int(card, 2 + i, NODE_FIELD(i), nodes(i))
      end do
      if (any(nodes(5:8) /= 0)) then
        call card_error(card, 'element '//itoa(eid)// &
            ': nodes N5-N8 given; 8-node shells are not supported')
        card%bad = .true.
      end if
      if (nodes(4) == 0) nodes(4) = nodes(3)
      call add_element(model%elements, eid, pid, ELEM_SHELL, nodes, card)
    end do
  end subroutine read_element_shell

  !> *ELEMENT_MASS (EID NID MASS PID, repeated: a point mass on a node) and
  !> *ELEMENT_MASS_NODE_SET (the same with a node set, MASS shared equally by its nodes).
  subroutine read_element_mass(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    type(card_t) :: card
    type(card_fields_t) :: f
    type(added_mass_t) :: item
    logical :: got, node_set
    node_set = trim(adjustl(options)) == 'NODE SET'
    if (len_trim(options) > 0 .and. .not. node_set) then
      call keyword_error(rd, 'option _'//trim(adjustl(options))//' is not supported '// &
                         '(_NODE_SET is)')
    end if
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      if (node_set) then                           ! (PID not used)
        call read_layout_card(rd, card, 'ELEMENT_MASS', 1, f, form_name=['NID ', 'NSID'])
      else
        call read_layout_card(rd, card, 'ELEMENT_MASS', 1, f)
      end if
      item = added_mass_t()
      item%target_kind = merge(ON_NODE_SET, ON_NODE, node_set)
      item%element_id = int_field(f, 'EID')
      item%target_id = int_field(f, trim(merge('NSID', 'NID ', node_set)))
      item%mass = real_field(f, 'MASS')
      if (card%bad) cycle
      if (item%target_id <= 0) then
        call card_error(card, 'field '//trim(merge('NSID', 'NID ', node_set))// &
                        ' must be positive (got '//itoa(item%target_id)//')')
      else if (item%mass < 0.0_wp) then
        call card_error(card, 'field MASS must not be negative (got '//rtoa(item%mass)//')')
      else
        item%src = source_t(card%file, card%line)
        call add_mass(model, item)
      end if
    end do
  end subroutine read_element_mass

  !> *ELEMENT_MASS_PART (PID ADDMASS FINMASS LCID, repeated) and *ELEMENT_MASS_PART_SET (a
  !> part set): non-structural mass spread over the part's nodes in proportion to their
  !> share of its mass; FINMASS > 0 asks for the mass that makes the part's total FINMASS.
  subroutine read_element_mass_part(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    type(card_t) :: card
    type(card_fields_t) :: f
    type(added_mass_t) :: item
    logical :: got, part_set
    integer :: lcid
    part_set = has_option(options, 'SET')
    if (len_trim(options) > 0 .and. .not. part_set) then
      call keyword_error(rd, 'options "'//trim(adjustl(options))//'" are not supported '// &
                         '(SET is)')
    end if
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      call read_layout_card(rd, card, 'ELEMENT_MASS_PART', 1, f, &
                            first_name=trim(merge('PSID', 'PID ', part_set)))
      item = added_mass_t()
      item%target_kind = merge(ON_PART_SET, ON_PART, part_set)
      item%target_id = int_field(f, trim(merge('PSID', 'PID ', part_set)))
      item%mass = real_field(f, 'ADDMASS')
      item%final_mass = real_field(f, 'FINMASS')
      lcid = int_field(f, 'LCID')
      if (card%bad) cycle
      if (item%target_id <= 0) then
        call card_error(card, 'field '//trim(merge('PSID', 'PID ', part_set))// &
                        ' must be positive (got '//itoa(item%target_id)//')')
      else if (item%mass < 0.0_wp .or. item%final_mass < 0.0_wp) then
        call card_error(card, 'fields ADDMASS and FINMASS must not be negative (got '// &
                        rtoa(item%mass)//', '//rtoa(item%final_mass)//')')
      else if (lcid /= 0) then
        call card_error(card, 'field LCID = '//itoa(lcid)//': mass that varies in time is '// &
                        'not supported (LCID must be 0)')
      else
        item%src = source_t(card%file, card%line)
        call add_mass(model, item)
      end if
    end do
  end subroutine read_element_mass_part

  !> Append an added mass.
  subroutine add_mass(model, item)
    type(model_t), intent(inout) :: model      !< model appended to
    type(added_mass_t), intent(in) :: item     !< the record
    type(added_mass_t), allocatable :: grown(:)
    if (.not. allocated(model%added_masses)) allocate(model%added_masses(0))
    if (model%n_added_masses == size(model%added_masses)) then
      allocate(grown(max(8, 2*model%n_added_masses)))
      grown(1:model%n_added_masses) = model%added_masses(1:model%n_added_masses)
      call move_alloc(grown, model%added_masses)
    end if
    model%n_added_masses = model%n_added_masses + 1
    model%added_masses(model%n_added_masses) = item
  end subroutine add_mass

  !> Check and append one element (node ids are resolved later).
  subroutine add_element(elements, eid, pid, keyword, nodes, card)
    type(elements_t), intent(inout) :: elements  !< element store
    integer, intent(in) :: eid, pid, keyword     !< id, part id, ELEM_SOLID/ELEM_SHELL
    integer, intent(in) :: nodes(8)              !< node ids
    type(card_t), intent(inout) :: card          !< the card, for messages
    integer :: k, nreq
    nreq = 4
    if (keyword == ELEM_SHELL) nreq = 3
    if (.not. card%bad) then
      if (eid <= 0) then
        call card_error(card, 'field EID: element id must be positive (got '// &
            itoa(eid)//')')
        card%bad = .true.
      else if (pid <= 0) then
        call card_error(card, 'element '//itoa(eid)//': field PID must be positive')
        card%bad = .true.
      else if (any(nodes(1:nreq) <= 0) .or. any(nodes < 0)) then
        call card_error(card, 'element '//itoa(eid)//': needs at least '// &
            itoa(nreq)//' positive node ids (N1-N'//itoa(nreq)//')')
        card%bad = .true.
      end if
    end if
    if (card%bad) return
    call grow_elements(elements)
    k = elements%n + 1
    elements%n = k
    elements%id(k) = eid
    elements%part_id(k) = pid
    elements%keyword(k) = keyword
    elements%node_ids(:, k) = nodes
    elements%src(k) = source_t(card%file, card%line)
  end subroutine add_element

  !> *PART: a heading card and a card PID SECID MID EOSID HGID GRAV ADPOPT TMID, repeated;
  !> *PART_CONTACT: a third card FS FD DC VC OPTT SFT SSF CPARM8 per part (FS, FD, DC are kept
  !> for the contacts whose FS is -1; the others read, not used).
  subroutine read_part(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    type(card_t) :: heading, card
    type(part_t) :: part
    type(part_t), allocatable :: grown(:)
    character(len=:), allocatable :: title
    type(card_t) :: card3
    type(card_fields_t) :: f
    logical :: got, contact_card, inertia_cards
    integer :: nread
    contact_card = has_option(options, 'CONTACT')
    inertia_cards = has_option(options, 'INERTIA')
    if (contact_card .and. inertia_cards) then
      call keyword_error(rd, 'options _INERTIA and _CONTACT together are not supported (give '// &
                         'the friction of the part in the contact)')
      contact_card = .false.
    end if
    nread = 0
    do
      call next_card(rd, heading, got, keep_blank=.true.)
      if (.not. got) then
        ! a *PART without a card at all (a truncated deck ends with it)
        if (nread == 0) call keyword_error(rd, 'no cards: give a heading card and the card '// &
                                           'PID SECID MID')
        exit
      end if
      nread = nread + 1
      call next_card(rd, card, got)
      if (.not. got) then
        if (len_trim(heading%text(1:heading%length)) > 0) &
          call card_error(heading, 'missing the card PID SECID MID after the heading')
        exit
      end if
      title = trim(adjustl(heading%text(1:min(heading%length, 80))))
      call read_layout_card(rd, card, 'PART', 2, f)
      part = part_t()
      part%title = title
      part%id = int_field(f, 'PID')
      part%section_id = int_field(f, 'SECID')
      part%material_id = int_field(f, 'MID')
      part%eos_id = int_field(f, 'EOSID')
      part%hourglass_id = int_field(f, 'HGID')
      part%src = source_t(card%file, card%line)
      if (inertia_cards) then
        call read_inertia_cards(rd, card, part, got)
        if (.not. got) exit
      end if
      if (contact_card) then
        call next_card(rd, card3, got, keep_blank=.true.)
        if (.not. got) then
          call card_error(card, 'part '//itoa(part%id)//': missing the *PART_CONTACT card '// &
                          'FS FD DC VC OPTT SFT SSF')
          exit
        end if
        call read_layout_card(rd, card3, 'PART', 3, f)   ! (VC OPTT SFT SSF read, not used)
        part%contact_fs = real_field(f, 'FS')
        part%contact_fd = real_field(f, 'FD')
        part%contact_dc = real_field(f, 'DC')
        part%has_contact = .true.
        if (card3%bad) cycle
        if (part%contact_fs < 0.0_wp .or. part%contact_fd < 0.0_wp .or. &
            part%contact_dc < 0.0_wp) call card_error(card3, 'part '//itoa(part%id)// &
            ': fields FS, FD and DC must not be negative')
      end if
      if (card%bad) cycle
      if (part%eos_id /= 0) then
        call card_error(card, 'part '//itoa(part%id)// &
            ': EOSID is given but equations of state are not supported')
        cycle
      end if
      if (.not. allocated(model%parts)) allocate(model%parts(0))
      if (model%n_parts == size(model%parts)) then
        allocate(grown(max(8, 2*model%n_parts)))
        grown(1:model%n_parts) = model%parts(1:model%n_parts)
        call move_alloc(grown, model%parts)
      end if
      model%n_parts = model%n_parts + 1
      model%parts(model%n_parts) = part
    end do
  end subroutine read_part

  !> The cards 3-5 of *PART_INERTIA (a rigid body's mass properties): XC YC ZC TM IRCS NODEID;
  !> IXX IXY IXZ IYY IYZ IZZ; VTX VTY VTZ VRX VRY VRZ. got is false when a card is missing.
  subroutine read_inertia_cards(rd, card2, part, got)
    type(reader_t), intent(inout) :: rd          !< reading state
    type(card_t), intent(inout) :: card2         !< the part's card PID SECID MID
    type(part_t), intent(inout) :: part          !< the part being read
    logical, intent(out) :: got                  !< all three cards were there
    character(len=*), parameter :: KEY = 'PART_INERTIA'
    type(card_t) :: card
    type(card_fields_t) :: f
    character(len=4), parameter :: TENSOR(6) = ['IXX ', 'IXY ', 'IXZ ', 'IYY ', 'IYZ ', 'IZZ ']
    character(len=4), parameter :: SPEED(6) = ['VTX ', 'VTY ', 'VTZ ', 'VRX ', 'VRY ', 'VRZ ']
    integer :: ircs, k
    call next_card(rd, card, got, keep_blank=.true.)
    if (.not. got) then
      call card_error(card2, 'part '//itoa(part%id)//': missing the *PART_INERTIA card XC '// &
                      'YC ZC TM IRCS NODEID')
      return
    end if
    call read_layout_card(rd, card, KEY, 3, f)
    part%inertia_centre = [real_field(f, 'XC'), real_field(f, 'YC'), real_field(f, 'ZC')]
    part%inertia_mass = real_field(f, 'TM')
    ircs = int_field(f, 'IRCS')
    part%inertia_node_id = int_field(f, 'NODEID')
    part%inertia_src = source_t(card%file, card%line)
    if (.not. card%bad) then
      if (.not. part%inertia_mass > 0.0_wp) then
        call card_error(card, 'part '//itoa(part%id)//': field TM (the body''s mass) must be '// &
                        'positive (got '//rtoa(part%inertia_mass)//')')
      else if (ircs /= 0) then
        call card_error(card, 'part '//itoa(part%id)//': field IRCS = '//itoa(ircs)// &
            ': an inertia tensor in a local coordinate system is not supported (IRCS must be 0)')
      else if (part%inertia_node_id < 0) then
        call card_error(card, 'part '//itoa(part%id)//': field NODEID must not be negative')
      end if
    end if
    if (card%bad) card2%bad = .true.
    call next_card(rd, card, got, keep_blank=.true.)
    if (.not. got) then
      call card_error(card2, 'part '//itoa(part%id)//': missing the *PART_INERTIA card IXX '// &
                      'IXY IXZ IYY IYZ IZZ')
      return
    end if
    call read_layout_card(rd, card, KEY, 4, f)
    do k = 1, 6
      part%inertia_tensor(k) = real_field(f, trim(TENSOR(k)))
    end do
    if (.not. card%bad .and. any(part%inertia_tensor([1, 4, 6]) < 0.0_wp)) call card_error( &
        card, 'part '//itoa(part%id)//': fields IXX, IYY and IZZ must not be negative')
    if (card%bad) card2%bad = .true.
    call next_card(rd, card, got, keep_blank=.true.)
    if (.not. got) then
      call card_error(card2, 'part '//itoa(part%id)//': missing the *PART_INERTIA card VTX '// &
                      'VTY VTZ VRX VRY VRZ')
      return
    end if
    call read_layout_card(rd, card, KEY, 5, f)
    do k = 1, 6
      part%inertia_velocity(k) = real_field(f, trim(SPEED(k)))
    end do
    if (card%bad) card2%bad = .true.
    part%has_inertia = .true.
  end subroutine read_inertia_cards

  !> *SECTION_SOLID: SECID ELFORM AET.
  subroutine read_section_solid(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    type(card_t) :: card
    type(card_fields_t) :: f
    type(section_t) :: section
    logical :: got
    call skip_title(rd, options)
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      call read_layout_card(rd, card, 'SECTION_SOLID', 1, f)
      section = section_t()
      section%kind = SECTION_SOLID
      section%id = int_field(f, 'SECID')
      section%elform = int_field(f, 'ELFORM')
      section%aet = int_field(f, 'AET')
      section%src = source_t(card%file, card%line)
      if (.not. card%bad) call add_section(model, section)
    end do
  end subroutine read_section_solid

  !> *HOURGLASS: HGID IHQ QM IBQ Q1 Q2 QB/VDC QW, one card per definition; IHQ and QM are
  !> used (by the one-point hexahedra of the parts naming HGID), the bulk-viscosity fields
  !> (IBQ Q1 Q2) and the shell fields (QB QW) are read and not used (mefem adds no bulk
  !> viscosity; its shells are rigid tool surfaces or plane-strain triangles).
  subroutine read_hourglass(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    type(card_t) :: card
    type(card_fields_t) :: f
    type(hourglass_t) :: hourglass
    type(hourglass_t), allocatable :: grown(:)
    logical :: got
    call skip_title(rd, options)
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      call read_layout_card(rd, card, 'HOURGLASS', 1, f)
      hourglass = hourglass_t()
      hourglass%id = int_field(f, 'HGID')
      hourglass%ihq = int_field(f, 'IHQ')
      hourglass%qm = real_field(f, 'QM')
      hourglass%src = source_t(card%file, card%line)
      if (card%bad) cycle
      if (hourglass%ihq < 0 .or. hourglass%ihq > 10) then
        call card_error(card, 'field IHQ must be 0 to 10 (got '//itoa(hourglass%ihq)//')')
        cycle
      end if
      if (hourglass%qm < 0.0_wp) then
        call card_error(card, 'field QM must not be negative (got '//rtoa(hourglass%qm)//')')
        cycle
      end if
      if (.not. allocated(model%hourglasses)) allocate(model%hourglasses(0))
      if (model%n_hourglasses == size(model%hourglasses)) then
        allocate(grown(max(4, 2*model%n_hourglasses)))
        grown(1:model%n_hourglasses) = model%hourglasses(1:model%n_hourglasses)
        call move_alloc(grown, model%hourglasses)
      end if
      model%n_hourglasses = model%n_hourglasses + 1
      model%hourglasses(model%n_hourglasses) = hourglass
    end do
  end subroutine read_hourglass

  !> *SECTION_SHELL: SECID ELFORM SHRF NIP PROPT QR ICOMP SETYP / T1 T2 T3 T4 NLOC.
  subroutine read_section_shell(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    type(card_t) :: card, card2
    type(card_fields_t) :: f
    type(section_t) :: section
    logical :: got
    integer :: icomp, i
    call skip_title(rd, options)
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      call read_layout_card(rd, card, 'SECTION_SHELL', 1, f)
      section = section_t()
      section%kind = SECTION_SHELL
      section%id = int_field(f, 'SECID')
      section%elform = int_field(f, 'ELFORM')
      section%shear_factor = real_field(f, 'SHRF')
      section%nip = int_field(f, 'NIP')
      icomp = int_field(f, 'ICOMP')
      section%src = source_t(card%file, card%line)
      call next_card(rd, card2, got, keep_blank=.true.)
      if (.not. got) then
        call card_error(card, 'section '//itoa(section%id)// &
            ': missing card 2 (T1 T2 T3 T4 NLOC)')
        exit
      end if
      call read_layout_card(rd, card2, 'SECTION_SHELL', 2, f)
      do i = 1, 4
        section%thickness(i) = real_field(f, 'T'//achar(iachar('0') + i))
      end do
      where (section%thickness(2:4) == 0.0_wp) section%thickness(2:4) = section%thickness(1)
      if (icomp /= 0) then
        call card_error(card, 'section '//itoa(section%id)// &
            ': ICOMP=1 (composite layers) is not supported')
        card%bad = .true.
      end if
      if (.not. (card%bad .or. card2%bad)) call add_section(model, section)
    end do
  end subroutine read_section_shell

  !> Consume the title card of a _TITLE option.
  subroutine skip_title(rd, options)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(card_t) :: card
    logical :: got
    if (has_option(options, 'TITLE')) call next_card(rd, card, got, keep_blank=.true.)
  end subroutine skip_title

  !> Append a section.
  subroutine add_section(model, section)
    type(model_t), intent(inout) :: model      !< model appended to
    type(section_t), intent(in) :: section     !< the section
    type(section_t), allocatable :: grown(:)
    if (.not. allocated(model%sections)) allocate(model%sections(0))
    if (model%n_sections == size(model%sections)) then
      allocate(grown(max(8, 2*model%n_sections)))
      grown(1:model%n_sections) = model%sections(1:model%n_sections)
      call move_alloc(grown, model%sections)
    end if
    model%n_sections = model%n_sections + 1
    model%sections(model%n_sections) = section
  end subroutine add_section

  !> Make room for one more node (capacity doubles).
  subroutine grow_nodes(nodes)
    type(nodes_t), intent(inout) :: nodes   !< node store
    integer :: cap
    integer, allocatable :: itmp(:)
    real(wp), allocatable :: xtmp(:,:)
    type(source_t), allocatable :: stmp(:)
    if (.not. allocated(nodes%id)) then
      allocate(nodes%id(1024), nodes%x(3, 1024), nodes%tc(1024), nodes%rc(1024), nodes%src(1024))
      return
    end if
    if (nodes%n < size(nodes%id)) return
    cap = 2*size(nodes%id)
    allocate(itmp(cap)); itmp(1:nodes%n) = nodes%id(1:nodes%n); call move_alloc(itmp, nodes%id)
    allocate(itmp(cap)); itmp(1:nodes%n) = nodes%tc(1:nodes%n); call move_alloc(itmp, nodes%tc)
    allocate(itmp(cap)); itmp(1:nodes%n) = nodes%rc(1:nodes%n); call move_alloc(itmp, nodes%rc)
    allocate(xtmp(3, cap)); xtmp(:, 1:nodes%n) = nodes%x(:, 1:nodes%n)
    call move_alloc(xtmp, nodes%x)
    allocate(stmp(cap)); stmp(1:nodes%n) = nodes%src(1:nodes%n); call move_alloc(stmp, nodes%src)
  end subroutine grow_nodes

  !> Make room for one more element (capacity doubles).
  subroutine grow_elements(elements)
    type(elements_t), intent(inout) :: elements   !< element store
    integer :: cap, n
    integer, allocatable :: itmp(:), ntmp(:,:)
    type(source_t), allocatable :: stmp(:)
    n = elements%n
    if (.not. allocated(elements%id)) then
      allocate(elements%id(1024), elements%part_id(1024), elements%keyword(1024), &
               elements%node_ids(8, 1024), elements%src(1024))
      return
    end if
    if (n < size(elements%id)) return
    cap = 2*size(elements%id)
    allocate(itmp(cap)); itmp(1:n) = elements%id(1:n); call move_alloc(itmp, elements%id)
    allocate(itmp(cap)); itmp(1:n) = elements%part_id(1:n); call move_alloc(itmp, elements%part_id)
    allocate(itmp(cap)); itmp(1:n) = elements%keyword(1:n); call move_alloc(itmp, elements%keyword)
    allocate(ntmp(8, cap)); ntmp(:, 1:n) = elements%node_ids(:, 1:n)
    call move_alloc(ntmp, elements%node_ids)
    allocate(stmp(cap)); stmp(1:n) = elements%src(1:n); call move_alloc(stmp, elements%src)
  end subroutine grow_elements

  !> Number of commas in a text.
  pure integer function count_commas(s)
    character(len=*), intent(in) :: s   !< the text
    integer :: i
    count_commas = 0
    do i = 1, len(s)
      if (s(i:i) == ',') count_commas = count_commas + 1
    end do
  end function count_commas

end module mefem_read_mesh
