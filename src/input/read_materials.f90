!> Keyword handlers for materials: *MAT_ELASTIC (*MAT_001), *MAT_PIECEWISE_LINEAR_PLASTICITY
!> (*MAT_024), *MAT_POWER_LAW_PLASTICITY (*MAT_018), *MAT_PLASTIC_KINEMATIC (*MAT_003),
!> *MAT_JOHNSON_COOK (*MAT_015), *MAT_SIMPLIFIED_JOHNSON_COOK (*MAT_098),
!> *MAT_MOONEY-RIVLIN_RUBBER (*MAT_027) and *MAT_RIGID (*MAT_020), each with the _TITLE option.
!> One material per keyword occurrence.
!>
!> Every value that would make the analysis meaningless is an error naming the field and
!> quoting the value. Curve references (LCSS, LCSR) and duplicate ids are checked later by
!> resolve_conditions.
module mefem_read_materials
  use mefem_kinds, only: wp
  use mefem_strings, only: itoa, rtoa
  use mefem_cards, only: reader_t, card_t, next_card, split_card, get_real, &
                         card_error, card_warning, keyword_error
  use mefem_card_helpers, only: read_title_card, reject_extra_cards, quoted_real
  use mefem_card_layouts, only: read_layout_card, real_field, int_field, card_fields_t, &
                                layout_default
  use mefem_model, only: model_t, material_t, source_t, MAT_ELASTIC, MAT_PIECEWISE_LINEAR, &
                         SPALL_PRINCIPAL, SPALL_PRESSURE_CUTOFF, SPALL_HYDROSTATIC, &
                         MAT_PLASTIC_KINEMATIC, MAT_JOHNSON_COOK, MAT_SIMPLIFIED_JOHNSON_COOK, &
                         MAT_POWER_LAW, MAT_RIGID, MAT_MOONEY_RIVLIN, add_erosion_t, &
                         EROSION_MXPRES, EROSION_MNEPS, EROSION_EFFEPS, EROSION_VOLEPS, &
                         EROSION_MNPRES, EROSION_SIGP1, EROSION_SIGVM, EROSION_MXEPS, &
                         EROSION_FAILTM
  implicit none
  private

  public :: read_mat_johnson_cook, read_mat_simplified_johnson_cook, last_material_id
  public :: read_mat_elastic, read_mat_piecewise_linear, read_mat_power_law, &
            read_mat_plastic_kinematic, &
            read_mat_mooney_rivlin, read_mat_rigid, material_keyword, read_mat_add_erosion

  integer, parameter :: W_10(8) = 10   !< standard 8 x 10 card

  !> MID of the material card read last (0: none yet): the keyword reader names a rejected
  !> material by it
  integer :: last_mid = 0

contains

  !> Keyword name of a material kind, for messages.
  function material_keyword(kind) result(s)
    integer, intent(in) :: kind   !< MAT_* code
    character(len=:), allocatable :: s
    select case (kind)
    case (MAT_ELASTIC)
      s = '*MAT_ELASTIC'
    case (MAT_PIECEWISE_LINEAR)
      s = '*MAT_PIECEWISE_LINEAR_PLASTICITY'
    case (MAT_POWER_LAW)
      s = '*MAT_POWER_LAW_PLASTICITY'
    case (MAT_MOONEY_RIVLIN)
      s = '*MAT_MOONEY-RIVLIN_RUBBER'
    case (MAT_RIGID)
      s = '*MAT_RIGID'
    case (MAT_PLASTIC_KINEMATIC)
      s = '*MAT_PLASTIC_KINEMATIC'
    case (MAT_JOHNSON_COOK)
      s = '*MAT_JOHNSON_COOK'
    case (MAT_SIMPLIFIED_JOHNSON_COOK)
      s = '*MAT_SIMPLIFIED_JOHNSON_COOK'
    case default
      s = '*MAT'
    end select
  end function material_keyword

  !> *MAT_ELASTIC: MID RO E PR DA DB K.
  subroutine read_mat_elastic(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    type(material_t) :: mat
    type(card_t) :: card
    type(card_fields_t) :: f
    logical :: got
    mat%kind = MAT_ELASTIC
    call read_title_card(rd, options, mat%title)
    call first_layout_card(rd, card, got, 'MAT_ELASTIC', 'MID RO E PR DA DB K', f, mat)
    if (.not. got) return
    mat%young = real_field(f, 'E')
    mat%poisson = real_field(f, 'PR')
    if (.not. card%bad) call check_elastic(card, mat, .true.)
    if (.not. card%bad) call add_material(model, mat)
    call reject_extra_cards(rd, 'material '//itoa(mat%id))
  end subroutine read_mat_elastic

  !> *MAT_PIECEWISE_LINEAR_PLASTICITY: MID RO E PR SIGY ETAN FAIL TDEL / C P LCSS LCSR VP /
  !> EPS1-8 / ES1-8. Missing EPS/ES cards count as blank.
  subroutine read_mat_piecewise_linear(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    character(len=*), parameter :: KEY = 'MAT_PIECEWISE_LINEAR_PLASTICITY'
    type(material_t) :: mat
    type(card_t) :: card, card2, card3, card4
    type(card_fields_t) :: f
    logical :: got, bad
    integer :: i
    mat%kind = MAT_PIECEWISE_LINEAR
    call read_title_card(rd, options, mat%title)
    call first_layout_card(rd, card, got, KEY, 'MID RO E PR SIGY ETAN FAIL TDEL', f, mat)
    if (.not. got) return
    mat%young = real_field(f, 'E')
    mat%poisson = real_field(f, 'PR')
    mat%yield_stress = real_field(f, 'SIGY')
    mat%tangent_modulus = real_field(f, 'ETAN')
    mat%failure_strain = real_field(f, 'FAIL')
    bad = card%bad
    if (.not. bad) call check_elastic(card, mat, .true.)
    bad = bad .or. card%bad
    ! card 2: C P LCSS LCSR VP
    call next_card(rd, card2, got, keep_blank=.true.)
    if (.not. got) then
      call card_error(card, 'material '//itoa(mat%id)//': missing card 2 (C P LCSS LCSR VP)')
      return
    end if
    call read_layout_card(rd, card2, KEY, 2, f)
    mat%cowper_c = real_field(f, 'C')
    mat%cowper_p = real_field(f, 'P')
    mat%lcss = int_field(f, 'LCSS')
    mat%lcsr = int_field(f, 'LCSR')
    mat%vp = real_field(f, 'VP')
    ! cards 3 and 4: EPS1-8 and ES1-8 (LS-DYNA wants them, blank or not; missing = blank)
    call next_card(rd, card3, got, keep_blank=.true.)
    if (got) then
      call read_layout_card(rd, card3, KEY, 3, f)
      do i = 1, 8
        mat%eps(i) = real_field(f, 'EPS'//itoa(i))
      end do
      call next_card(rd, card4, got, keep_blank=.true.)
      if (got) then
        call read_layout_card(rd, card4, KEY, 4, f)
        do i = 1, 8
          mat%es(i) = real_field(f, 'ES'//itoa(i))
        end do
        bad = bad .or. card4%bad
      end if
      bad = bad .or. card3%bad
    else
      card3 = card2
      card4 = card2
    end if
    bad = bad .or. card2%bad
    if (.not. bad) call check_piecewise_linear(card, card2, card3, card4, mat, bad)
    if (.not. bad) call add_material(model, mat)
    call reject_extra_cards(rd, 'material '//itoa(mat%id))
  end subroutine read_mat_piecewise_linear

  !> Checks of *MAT_024 beyond the elastic constants: yield, hardening, failure, rate
  !> parameters and the EPS/ES table (points are the leading ES values that are nonzero).
  subroutine check_piecewise_linear(card, card2, card3, card4, mat, bad)
    type(card_t), intent(in) :: card, card2, card3, card4   !< the four cards
    type(material_t), intent(inout) :: mat                  !< the material
    logical, intent(inout) :: bad                           !< set on any error
    character(len=:), allocatable :: who
    integer :: i, n
    who = 'material '//itoa(mat%id)//': '
    if (mat%yield_stress < 0.0_wp) call fail(card, who//'field SIGY must not be negative '// &
        quoted_real(mat%yield_stress))
    if (mat%tangent_modulus < 0.0_wp .or. mat%tangent_modulus >= mat%young) &
      call fail(card, who//'field ETAN must be >= 0 and < E = '//rtoa(mat%young)//' '// &
                quoted_real(mat%tangent_modulus))
    if (mat%failure_strain < 0.0_wp) call fail(card, who//'field FAIL < 0 (user failure '// &
        'subroutine) is not supported '//quoted_real(mat%failure_strain))
    if (mat%cowper_c < 0.0_wp) call fail(card2, who//'field C must not be negative '// &
        quoted_real(mat%cowper_c))
    if (mat%cowper_p < 0.0_wp .or. (mat%cowper_c > 0.0_wp .and. mat%cowper_p == 0.0_wp)) &
      call fail(card2, who//'field P must be > 0 when C is given '//quoted_real(mat%cowper_p))
    if (mat%lcss < 0) call fail(card2, who//'field LCSS must not be negative (got '// &
        itoa(mat%lcss)//')')
    if (mat%lcsr < 0) call fail(card2, who//'field LCSR must not be negative (got '// &
        itoa(mat%lcsr)//')')
    if (mat%vp /= 0.0_wp .and. mat%vp /= 1.0_wp .and. mat%vp /= -1.0_wp) &
      call fail(card2, who//'field VP must be -1, 0 or 1 '//quoted_real(mat%vp))
    ! the EPS/ES table
    n = 0
    do i = 8, 1, -1
      if (mat%es(i) /= 0.0_wp) then
        n = i
        exit
      end if
    end do
    mat%n_points = n
    if (n == 1) call fail(card4, who//'EPS/ES table: give at least 2 points (only ES1 is set)')
    do i = 1, n
      if (mat%es(i) <= 0.0_wp) call fail(card4, who//'field ES'//itoa(i)// &
          ' must be > 0 '//quoted_real(mat%es(i)))
      if (mat%eps(i) < 0.0_wp) call fail(card3, who//'field EPS'//itoa(i)// &
          ' must not be negative '//quoted_real(mat%eps(i)))
      if (i > 1) then
        if (mat%eps(i) <= mat%eps(i-1)) call fail(card3, who//'field EPS'//itoa(i)// &
            ' must be greater than EPS'//itoa(i-1)//' = '//rtoa(mat%eps(i-1))//' '// &
            quoted_real(mat%eps(i)))
      end if
    end do
    if (mat%lcss == 0 .and. n == 0 .and. mat%yield_stress <= 0.0_wp) call fail(card, who// &
        'field SIGY must be > 0 when neither LCSS nor an EPS/ES table is given '// &
        quoted_real(mat%yield_stress))
  contains
    !> Report and remember an error.
    subroutine fail(where_card, message)
      type(card_t), intent(in) :: where_card     !< the card with the field
      character(len=*), intent(in) :: message    !< what is wrong
      call card_error(where_card, message)
      bad = .true.
    end subroutine fail
  end subroutine check_piecewise_linear

  !> *MAT_POWER_LAW_PLASTICITY: MID RO E PR K N SRC SRP / SIGY VP EPSF.
  subroutine read_mat_power_law(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    character(len=*), parameter :: KEY = 'MAT_POWER_LAW_PLASTICITY'
    type(material_t) :: mat
    type(card_t) :: card, card2
    type(card_fields_t) :: f
    logical :: got, bad
    character(len=:), allocatable :: who
    mat%kind = MAT_POWER_LAW
    call read_title_card(rd, options, mat%title)
    call first_layout_card(rd, card, got, KEY, 'MID RO E PR K N SRC SRP', f, mat)
    if (.not. got) return
    mat%young = real_field(f, 'E')
    mat%poisson = real_field(f, 'PR')
    mat%k_strength = real_field(f, 'K')
    mat%n_exponent = real_field(f, 'N')
    mat%cowper_c = real_field(f, 'SRC')
    mat%cowper_p = real_field(f, 'SRP')
    bad = card%bad
    if (.not. bad) call check_elastic(card, mat, .true.)
    bad = bad .or. card%bad
    who = 'material '//itoa(mat%id)//': '
    call next_card(rd, card2, got, keep_blank=.true.)
    if (got) then
      call read_layout_card(rd, card2, KEY, 2, f)
      mat%yield_stress = real_field(f, 'SIGY')
      mat%vp = real_field(f, 'VP')
      mat%failure_strain = real_field(f, 'EPSF')
      bad = bad .or. card2%bad
    else
      card2 = card
    end if
    if (.not. bad) then
      if (mat%k_strength <= 0.0_wp) call fail(card, who//'field K must be > 0 '// &
          quoted_real(mat%k_strength))
      ! N > 1 is allowed: the seed paper's law sigma_y0 (1 + a e_p)^b has b = 1.1
      if (mat%n_exponent < 0.0_wp) call fail(card, who// &
          'field N must be >= 0 '//quoted_real(mat%n_exponent))
      if (mat%yield_stress < 0.0_wp) call fail(card2, who//'field SIGY must not be '// &
          'negative '//quoted_real(mat%yield_stress))
    end if
    if (.not. bad) call check_rate_and_failure(card, card2, mat, 'EPSF', bad)
    if (.not. bad) call add_material(model, mat)
    call reject_extra_cards(rd, 'material '//itoa(mat%id))
  contains
    !> Report and remember an error.
    subroutine fail(where_card, message)
      type(card_t), intent(in) :: where_card     !< the card with the field
      character(len=*), intent(in) :: message    !< what is wrong
      call card_error(where_card, message)
      bad = .true.
    end subroutine fail
  end subroutine read_mat_power_law

  !> *MAT_PLASTIC_KINEMATIC (*MAT_003): MID RO E PR SIGY ETAN BETA / SRC SRP FS VP. Bilinear
  !> J2 plasticity with mixed hardening (BETA 0 kinematic, 1 isotropic); the rate and failure
  !> fields are read and, when set, a warning says they are not modelled.
  subroutine read_mat_plastic_kinematic(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    character(len=*), parameter :: KEY = 'MAT_PLASTIC_KINEMATIC'
    type(material_t) :: mat
    type(card_t) :: card, card2
    type(card_fields_t) :: f
    logical :: got, bad
    character(len=:), allocatable :: who
    mat%kind = MAT_PLASTIC_KINEMATIC
    call read_title_card(rd, options, mat%title)
    call first_layout_card(rd, card, got, KEY, 'MID RO E PR SIGY ETAN BETA', f, mat)
    if (.not. got) return
    mat%young = real_field(f, 'E')
    mat%poisson = real_field(f, 'PR')
    mat%yield_stress = real_field(f, 'SIGY')
    mat%tangent_modulus = real_field(f, 'ETAN')
    mat%beta = real_field(f, 'BETA')
    bad = card%bad
    if (.not. bad) call check_elastic(card, mat, .true.)
    bad = bad .or. card%bad
    who = 'material '//itoa(mat%id)//': '
    ! card 2: SRC SRP FS VP (optional: blank or missing = 0)
    call next_card(rd, card2, got, keep_blank=.true.)
    if (got) then
      call read_layout_card(rd, card2, KEY, 2, f)
      mat%cowper_c = real_field(f, 'SRC')
      mat%cowper_p = real_field(f, 'SRP')
      mat%failure_strain = real_field(f, 'FS')
      mat%vp = real_field(f, 'VP')
      bad = bad .or. card2%bad
    else
      card2 = card
    end if
    if (.not. bad) then
      if (.not. (mat%yield_stress > 0.0_wp)) call fail_field(card, who//'field SIGY must be '// &
          '> 0 '//quoted_real(mat%yield_stress), bad)
      if (mat%tangent_modulus < 0.0_wp .or. mat%tangent_modulus >= mat%young) &
        call fail_field(card, who//'field ETAN must be >= 0 and < E = '//rtoa(mat%young)// &
                        ' '//quoted_real(mat%tangent_modulus), bad)
      if (mat%beta < 0.0_wp .or. mat%beta > 1.0_wp) call fail_field(card, who//'field BETA '// &
          'must be 0 (kinematic) to 1 (isotropic hardening) '//quoted_real(mat%beta), bad)
    end if
    if (.not. bad) call check_rate_and_failure(card2, card2, mat, 'FS', bad)
    if (.not. bad) call add_material(model, mat)
    call reject_extra_cards(rd, 'material '//itoa(mat%id))
  end subroutine read_mat_plastic_kinematic

  !> *MAT_ADD_EROSION (_TITLE): failure criteria added to material MID (explicit: element
  !> erosion). Card 1 MID EXCL MXPRES MNEPS EFFEPS VOLEPS NUMFIP NCS; card 2 MNPRES SIGP1
  !> SIGVM MXEPS EPSSH SIGTH IMPULSE FAILTM; further cards (damage models: IDAM, ...) must be
  !> blank. A criterion is used when its value is not EXCL (default 0: blank and 0 unused).
  subroutine read_mat_add_erosion(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    character(len=*), parameter :: KEY = 'MAT_ADD_EROSION'
    type(card_t) :: card, card2, card3
    type(card_fields_t) :: f
    type(add_erosion_t) :: item
    type(add_erosion_t), allocatable :: grown(:)
    character(len=80) :: title
    character(len=:), allocatable :: who
    logical :: got, bad
    real(wp) :: damage, epssh, sigth, impulse
    integer :: k
    call read_title_card(rd, options, title)
    call next_card(rd, card, got)
    if (.not. got) then
      call keyword_error(rd, 'missing card 1 (MID EXCL MXPRES MNEPS EFFEPS VOLEPS NUMFIP NCS)')
      return
    end if
    call read_layout_card(rd, card, KEY, 1, f)
    item%material_id = int_field(f, 'MID')
    item%exclusion = real_field(f, 'EXCL')
    item%limit(EROSION_MXPRES) = real_field(f, 'MXPRES')
    item%limit(EROSION_MNEPS) = real_field(f, 'MNEPS')
    item%limit(EROSION_EFFEPS) = real_field(f, 'EFFEPS')
    item%limit(EROSION_VOLEPS) = real_field(f, 'VOLEPS')
    item%conditions = int_field(f, 'NCS')
    item%src = source_t(card%file, card%line)
    bad = card%bad
    who = 'material '//itoa(item%material_id)//': '
    call next_card(rd, card2, got, keep_blank=.true.)
    epssh = 0.0_wp
    sigth = 0.0_wp
    impulse = 0.0_wp
    if (got) then
      call read_layout_card(rd, card2, KEY, 2, f)
      item%limit(EROSION_MNPRES) = real_field(f, 'MNPRES')
      item%limit(EROSION_SIGP1) = real_field(f, 'SIGP1')
      item%limit(EROSION_SIGVM) = real_field(f, 'SIGVM')
      item%limit(EROSION_MXEPS) = real_field(f, 'MXEPS')
      epssh = real_field(f, 'EPSSH')
      sigth = real_field(f, 'SIGTH')
      impulse = real_field(f, 'IMPULSE')
      item%limit(EROSION_FAILTM) = real_field(f, 'FAILTM')
      bad = bad .or. card2%bad
      if (.not. card2%bad .and. (epssh /= item%exclusion .or. sigth /= item%exclusion .or. &
          impulse /= item%exclusion)) then
        call card_error(card2, who//'EPSSH (shear strain) and the Tuler-Butcher criterion '// &
            '(SIGTH, IMPULSE) are not supported: give them as EXCL (or blank)')
        bad = .true.
      end if
    end if
    do                                            ! damage cards (IDAM ...): blank only
      call next_card(rd, card3, got, keep_blank=.true.)
      if (.not. got) exit
      if (len_trim(card3%text(1:card3%length)) == 0) cycle
      call split_card(rd, card3, W_10)
      do k = 1, 8
        call get_real(card3, k, 'field '//itoa(k), damage)
        if (damage /= 0.0_wp .and. .not. card3%bad) then
          call card_error(card3, who//'the damage models of *MAT_ADD_EROSION (IDAM, DMGTYP, '// &
              '...) are not supported: leave its cards after card 2 blank')
          bad = .true.
          exit
        end if
      end do
    end do
    if (bad) return
    if (item%material_id <= 0) then
      call card_error(card, 'field MID must be a positive material id (got '// &
                      itoa(item%material_id)//')')
      return
    end if
    if (item%conditions < 1) then
      call card_error(card, who//'field NCS must be >= 1 (got '//itoa(item%conditions)//')')
      return
    end if
    if (.not. allocated(model%add_erosions)) allocate(model%add_erosions(0))
    if (model%n_add_erosions == size(model%add_erosions)) then
      allocate(grown(max(4, 2*model%n_add_erosions)))
      grown(1:model%n_add_erosions) = model%add_erosions(1:model%n_add_erosions)
      call move_alloc(grown, model%add_erosions)
    end if
    model%n_add_erosions = model%n_add_erosions + 1
    model%add_erosions(model%n_add_erosions) = item
  end subroutine read_mat_add_erosion

  !> *MAT_JOHNSON_COOK (*MAT_015): MID RO G E PR DTF VP RATEOP / A B N C M TM TR EPSO / CP PC
  !> SPALL IT D1 D2 D3 D4 / [D5 C2 EROD EFMIN NUMINT]. J2 plasticity with the flow stress
  !> (A + B alpha^N)(1 + C ln(rate/EPSO))(1 - T*^M) and adiabatic heating from the plastic work
  !> (CP > 0); without an *EOS the pressure comes from the bulk modulus of G (or E) and PR.
  !> Solids take G (E = 2 G (1 + PR)); E serves when G is 0.
  subroutine read_mat_johnson_cook(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    character(len=*), parameter :: KEY = 'MAT_JOHNSON_COOK'
    type(material_t) :: mat
    type(card_t) :: card, card2, card3, card4
    type(card_fields_t) :: f
    logical :: got, bad, got4
    real(wp) :: shear, dtf, pc, spall, damage(5), erod, efmin
    integer :: rateop, k
    character(len=:), allocatable :: who
    mat%kind = MAT_JOHNSON_COOK
    call read_title_card(rd, options, mat%title)
    call first_layout_card(rd, card, got, KEY, 'MID RO G E PR DTF VP RATEOP', f, mat)
    if (.not. got) return
    shear = real_field(f, 'G')
    mat%young = real_field(f, 'E')
    mat%poisson = real_field(f, 'PR')
    dtf = real_field(f, 'DTF')
    mat%vp = real_field(f, 'VP')
    rateop = int_field(f, 'RATEOP')
    bad = card%bad
    who = 'material '//itoa(mat%id)//': '
    call next_card(rd, card2, got, keep_blank=.true.)
    if (.not. got) then
      call card_error(card, who//'missing card 2 (A B N C M TM TR EPSO)')
      return
    end if
    call read_layout_card(rd, card2, KEY, 2, f)
    mat%jc_a = real_field(f, 'A')
    mat%jc_b = real_field(f, 'B')
    mat%n_exponent = real_field(f, 'N')
    mat%jc_c = real_field(f, 'C')
    mat%jc_m = real_field(f, 'M')
    mat%melt_temperature = real_field(f, 'TM')
    mat%room_temperature = real_field(f, 'TR')
    mat%reference_rate = real_field(f, 'EPSO')
    bad = bad .or. card2%bad
    call next_card(rd, card3, got, keep_blank=.true.)
    if (.not. got) then
      call card_error(card2, who//'missing card 3 (CP PC SPALL IT D1 D2 D3 D4)')
      return
    end if
    call read_layout_card(rd, card3, KEY, 3, f)
    mat%heat_capacity = real_field(f, 'CP')
    pc = real_field(f, 'PC')
    spall = real_field(f, 'SPALL')
    do k = 1, 4
      damage(k) = real_field(f, 'D'//itoa(k))
    end do
    bad = bad .or. card3%bad
    damage(5) = 0.0_wp
    erod = 0.0_wp
    efmin = layout_default(KEY, 4, 'EFMIN')
    call next_card(rd, card4, got4, keep_blank=.true.)          ! optional
    if (got4) then
      call read_layout_card(rd, card4, KEY, 4, f)
      damage(5) = real_field(f, 'D5')
      erod = real_field(f, 'EROD')
      efmin = real_field(f, 'EFMIN')
      bad = bad .or. card4%bad
    end if
    call reject_extra_cards(rd, 'material '//itoa(mat%id))
    if (bad) return
    ! elastic constants: G for solids (E when G is not given)
    if (shear > 0.0_wp) then
      mat%young = 2.0_wp*shear*(1.0_wp + mat%poisson)
    else if (shear < 0.0_wp .or. .not. mat%young > 0.0_wp) then
      call fail_field(card, who//'field G (shear modulus) must be > 0 (or E > 0 when G is '// &
          'not given) '//quoted_real(shear), bad)
    end if
    if (.not. bad) call check_elastic(card, mat, .false.)
    bad = bad .or. card%bad
    if (rateop /= 0) call fail_field(card, who//'field RATEOP = '//itoa(rateop)//' is not '// &
        'supported: 0, the Johnson-Cook rate term 1 + C ln(rate/EPSO), is', bad)
    if (mat%vp /= 0.0_wp .and. mat%vp /= 1.0_wp) call fail_field(card, who// &
        'field VP must be 0 or 1 '//quoted_real(mat%vp), bad)
    call johnson_cook_strength(card2, mat, bad)
    if (mat%jc_m < 0.0_wp) call fail_field(card2, who//'field M must not be negative '// &
        quoted_real(mat%jc_m), bad)
    if (mat%melt_temperature /= 0.0_wp .and. .not. mat%melt_temperature > &
        mat%room_temperature) call fail_field(card2, who//'field TM (melting temperature) '// &
        'must be above TR (room temperature) '//quoted_real(mat%melt_temperature), bad)
    if (mat%heat_capacity < 0.0_wp) call fail_field(card3, who//'field CP must not be '// &
        'negative '//quoted_real(mat%heat_capacity), bad)
    if (mat%heat_capacity > 0.0_wp .and. mat%melt_temperature > mat%room_temperature .and. &
        .not. mat%jc_m > 0.0_wp) call fail_field(card2, who//'field M must be > 0 for the '// &
        'thermal softening 1 - T*^M (CP and TM are given)', bad)
    ! failure: D1 or D2 switch it on; D3-D5 only scale D1 + D2 exp(D3 s*)
    mat%jc_fails = damage(1) /= 0.0_wp .or. damage(2) /= 0.0_wp
    mat%jc_damage = damage
    mat%jc_min_failure_strain = efmin
    if (.not. mat%jc_fails .and. any(damage(3:5) /= 0.0_wp)) call fail_field(card3, who// &
        'D3, D4 and D5 scale the failure strain D1 + D2 exp(D3 s*): give D1 or D2 (both 0: '// &
        'no failure)', bad)
    if (efmin < 0.0_wp) call fail_field(card4, who//'field EFMIN must not be negative '// &
        quoted_real(efmin), bad)
    ! spall (SPALL 0 is 2; PC = 0, blank, is no cutoff and no spall) and EROD
    select case (nint(spall))
    case (0, 2)
      if (pc < 0.0_wp) mat%spall = SPALL_PRINCIPAL
    case (1)
      if (pc < 0.0_wp) mat%spall = SPALL_PRESSURE_CUTOFF
    case (3)
      if (pc < 0.0_wp) mat%spall = SPALL_HYDROSTATIC
    end select
    if (spall /= real(nint(spall), wp) .or. spall < 0.0_wp .or. spall > 3.0_wp) &
      call fail_field(card3, who//'field SPALL must be 0, 1, 2 or 3 '//quoted_real(spall), bad)
    if (pc > 0.0_wp) call fail_field(card3, who//'field PC (the tensile pressure cutoff) must '// &
        'be negative, or 0 for none '//quoted_real(pc), bad)
    mat%pressure_cutoff = pc
    mat%jc_keep_failed = mat%jc_fails .and. erod /= 0.0_wp
    if (bad) return
    ! read, not modelled: say so where LS-DYNA would compute something else
    if (mat%vp == 1.0_wp .and. mat%jc_c /= 0.0_wp) call card_warning(card, who//'VP = 1 '// &
        '(viscoplastic) is computed as VP = 0: the yield stress is scaled by the total '// &
        'strain rate (doc/theory.md section 4)')
    if (dtf /= 0.0_wp) call card_warning(card, who//'DTF ignored: no element is eroded by '// &
        'its time step')
    if (pc == 0.0_wp .and. spall /= 0.0_wp) call card_warning(card3, who//'SPALL = '// &
        trim(rtoa(spall))//' with PC = 0: no pressure cutoff and no spall (give PC < 0, the '// &
        'tensile pressure limit)')
    if (erod /= 0.0_wp .and. .not. mat%jc_fails) call card_warning(card4, who//'EROD ignored: '// &
        'no failure model (D1 and D2 are 0)')
    call add_material(model, mat)
  end subroutine read_mat_johnson_cook

  !> *MAT_SIMPLIFIED_JOHNSON_COOK (*MAT_098): MID RO E PR VP / A B N C PSFAIL SIGMAX SIGSAT
  !> EPSO. The Johnson-Cook flow stress without the thermal term, the hardening capped at
  !> SIGMAX.
  subroutine read_mat_simplified_johnson_cook(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    character(len=*), parameter :: KEY = 'MAT_SIMPLIFIED_JOHNSON_COOK'
    real(wp), parameter :: UNSET = 1.0e28_wp     !< the table's default of PSFAIL, SIGMAX, SIGSAT
    type(material_t) :: mat
    type(card_t) :: card, card2
    type(card_fields_t) :: f
    logical :: got, bad
    real(wp) :: psfail, sigsat
    character(len=:), allocatable :: who
    mat%kind = MAT_SIMPLIFIED_JOHNSON_COOK
    call read_title_card(rd, options, mat%title)
    call first_layout_card(rd, card, got, KEY, 'MID RO E PR VP', f, mat)
    if (.not. got) return
    mat%young = real_field(f, 'E')
    mat%poisson = real_field(f, 'PR')
    mat%vp = real_field(f, 'VP')
    bad = card%bad
    if (.not. bad) call check_elastic(card, mat, .true.)
    bad = bad .or. card%bad
    who = 'material '//itoa(mat%id)//': '
    call next_card(rd, card2, got, keep_blank=.true.)
    if (.not. got) then
      call card_error(card, who//'missing card 2 (A B N C PSFAIL SIGMAX SIGSAT EPSO)')
      return
    end if
    call read_layout_card(rd, card2, KEY, 2, f)
    mat%jc_a = real_field(f, 'A')
    mat%jc_b = real_field(f, 'B')
    mat%n_exponent = real_field(f, 'N')
    mat%jc_c = real_field(f, 'C')
    psfail = real_field(f, 'PSFAIL')
    mat%max_stress = real_field(f, 'SIGMAX')
    sigsat = real_field(f, 'SIGSAT')
    mat%reference_rate = real_field(f, 'EPSO')
    bad = bad .or. card2%bad
    call reject_extra_cards(rd, 'material '//itoa(mat%id))
    if (bad) return
    if (mat%vp /= 0.0_wp .and. mat%vp /= 1.0_wp) call fail_field(card, who// &
        'field VP must be 0 or 1 '//quoted_real(mat%vp), bad)
    call johnson_cook_strength(card2, mat, bad)
    if (mat%max_stress >= UNSET .or. mat%max_stress == 0.0_wp) mat%max_stress = 0.0_wp
    if (mat%max_stress < 0.0_wp) call fail_field(card2, who//'field SIGMAX must be > 0 '// &
        quoted_real(mat%max_stress), bad)
    if (bad) return
    if (mat%vp == 1.0_wp .and. mat%jc_c /= 0.0_wp) call card_warning(card, who//'VP = 1 '// &
        '(viscoplastic) is computed as VP = 0: the yield stress is scaled by the total '// &
        'strain rate (doc/theory.md section 4)')
    if (psfail > 0.0_wp .and. psfail < UNSET) mat%failure_strain = psfail
    if (sigsat > 0.0_wp .and. sigsat < UNSET) call card_warning(card2, who//'SIGSAT '// &
        '(the cap of the flow stress with rate effects) is not modelled: only SIGMAX caps it')
    call add_material(model, mat)
  end subroutine read_mat_simplified_johnson_cook

  !> The strength fields shared by *MAT_015 and *MAT_098: A > 0, B, N, C >= 0; EPSO 0 is read
  !> as 1 (per time unit of the deck) with a warning when C is given.
  subroutine johnson_cook_strength(card2, mat, bad)
    type(card_t), intent(in) :: card2            !< the card of A B N C ... EPSO
    type(material_t), intent(inout) :: mat       !< the material
    logical, intent(inout) :: bad                !< set on any error
    character(len=:), allocatable :: who
    who = 'material '//itoa(mat%id)//': '
    if (.not. mat%jc_a > 0.0_wp) call fail_field(card2, who//'field A (the yield stress) '// &
        'must be > 0 '//quoted_real(mat%jc_a), bad)
    if (mat%jc_b < 0.0_wp) call fail_field(card2, who//'field B must not be negative '// &
        quoted_real(mat%jc_b), bad)
    if (mat%n_exponent < 0.0_wp) call fail_field(card2, who//'field N must not be negative '// &
        quoted_real(mat%n_exponent), bad)
    if (mat%jc_c < 0.0_wp) call fail_field(card2, who//'field C must not be negative '// &
        quoted_real(mat%jc_c), bad)
    if (mat%reference_rate < 0.0_wp) call fail_field(card2, who//'field EPSO must not be '// &
        'negative '//quoted_real(mat%reference_rate), bad)
    if (mat%reference_rate == 0.0_wp) then
      mat%reference_rate = 1.0_wp
      if (mat%jc_c /= 0.0_wp .and. .not. bad) call card_warning(card2, who//'EPSO = 0 read '// &
          'as 1 per time unit of the deck (the reference strain rate of C ln(rate/EPSO))')
    end if
  end subroutine johnson_cook_strength

  !> The strain-rate and failure fields of *MAT_018 and *MAT_003 (SRC, SRP on rate_card; VP
  !> and the failure strain, named fs_name, on fail_card): checked.
  subroutine check_rate_and_failure(rate_card, fail_card, mat, fs_name, bad)
    type(card_t), intent(in) :: rate_card, fail_card   !< the cards holding the fields
    type(material_t), intent(in) :: mat                !< the material
    character(len=*), intent(in) :: fs_name            !< name of the failure strain field
    logical, intent(inout) :: bad                      !< set on any error
    character(len=:), allocatable :: who
    logical :: was_bad
    who = 'material '//itoa(mat%id)//': '
    was_bad = bad
    if (mat%cowper_c < 0.0_wp) call fail_field(rate_card, who//'field SRC must not be '// &
        'negative '//quoted_real(mat%cowper_c), bad)
    if (mat%cowper_p < 0.0_wp .or. (mat%cowper_c > 0.0_wp .and. mat%cowper_p == 0.0_wp)) &
      call fail_field(rate_card, who//'field SRP must be > 0 when SRC is given '// &
                      quoted_real(mat%cowper_p), bad)
    if (mat%vp /= 0.0_wp .and. mat%vp /= 1.0_wp) call fail_field(fail_card, who// &
        'field VP must be 0 or 1 '//quoted_real(mat%vp), bad)
    if (mat%failure_strain < 0.0_wp) call fail_field(fail_card, who//'field '//fs_name// &
        ' must not be negative '//quoted_real(mat%failure_strain), bad)
    if (bad .and. .not. was_bad) return

  end subroutine check_rate_and_failure

  !> Report an error at a card and remember it.
  subroutine fail_field(where_card, message, bad)
    type(card_t), intent(in) :: where_card     !< the card with the field
    character(len=*), intent(in) :: message    !< what is wrong
    logical, intent(inout) :: bad              !< set
    call card_error(where_card, message)
    bad = .true.
  end subroutine fail_field

  !> *MAT_MOONEY-RIVLIN_RUBBER: MID RO PR A B REF / SGL SW ST LCID. PR is Poisson's ratio
  !> (near 0.5 for rubber); E is not an input: the small-strain equivalent
  !> E = 2 G (1 + PR) with G = 2 (A + B) is stored for time-step and contact estimates.
  subroutine read_mat_mooney_rivlin(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    character(len=*), parameter :: KEY = 'MAT_MOONEY-RIVLIN_RUBBER'
    type(material_t) :: mat
    type(card_t) :: card, card2
    type(card_fields_t) :: f
    logical :: got, bad
    real(wp) :: ref
    integer :: lcid
    character(len=:), allocatable :: who
    mat%kind = MAT_MOONEY_RIVLIN
    call read_title_card(rd, options, mat%title)
    call first_layout_card(rd, card, got, KEY, 'MID RO PR A B REF', f, mat)
    if (.not. got) return
    mat%poisson = real_field(f, 'PR')
    mat%mr_a = real_field(f, 'A')
    mat%mr_b = real_field(f, 'B')
    ref = real_field(f, 'REF')
    bad = card%bad
    who = 'material '//itoa(mat%id)//': '
    lcid = 0
    call next_card(rd, card2, got, keep_blank=.true.)
    if (got) then
      call read_layout_card(rd, card2, KEY, 2, f)
      lcid = int_field(f, 'LCID')
      bad = bad .or. card2%bad
      if (.not. bad .and. lcid /= 0) then
        call card_error(card2, who//'field LCID: fitting A and B to test data (LCID = '// &
            itoa(lcid)//') is not supported; give A and B')
        bad = .true.
      end if
    end if
    if (.not. bad) then
      mat%young = 4.0_wp*(mat%mr_a + mat%mr_b)*(1.0_wp + mat%poisson)
      call check_elastic(card, mat, .false.)
      bad = card%bad
    end if
    if (.not. bad) then
      if (mat%mr_a + mat%mr_b <= 0.0_wp) then
        call card_error(card, who//'the shear modulus 2(A+B) must be > 0 (got A = '// &
            rtoa(mat%mr_a)//', B = '//rtoa(mat%mr_b)//')')
        bad = .true.
      end if
      if (ref /= 0.0_wp) then
        call card_error(card, who//'field REF: a reference geometry '// &
            '(*INITIAL_FOAM_REFERENCE_GEOMETRY) is not supported '//quoted_real(ref))
        bad = .true.
      end if
    end if
    if (.not. bad) call add_material(model, mat)
    call reject_extra_cards(rd, 'material '//itoa(mat%id))
  end subroutine read_mat_mooney_rivlin

  !> *MAT_RIGID: MID RO E PR N COUPLE M ALIAS / CMO CON1 CON2 / [LCO or A1 A2 A3 V1 V2 V3].
  !> Card 3 (output axes) is accepted and not used.
  subroutine read_mat_rigid(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    character(len=*), parameter :: KEY = 'MAT_RIGID'
    type(material_t) :: mat
    type(card_t) :: card, card2, card3
    type(card_fields_t) :: f
    logical :: got, bad
    real(wp) :: coupling_n
    real(wp) :: cmo
    character(len=:), allocatable :: who
    mat%kind = MAT_RIGID
    call read_title_card(rd, options, mat%title)
    call first_layout_card(rd, card, got, KEY, 'MID RO E PR N COUPLE M ALIAS', f, mat)
    if (.not. got) return
    mat%young = real_field(f, 'E')
    mat%poisson = real_field(f, 'PR')
    coupling_n = real_field(f, 'N')
    bad = card%bad
    if (.not. bad) call check_elastic(card, mat, .true.)
    bad = bad .or. card%bad
    who = 'material '//itoa(mat%id)//': '
    if (.not. bad .and. coupling_n /= 0.0_wp) then
      call card_error(card, who//'field N: coupling with MADYMO/CAL3D is not supported '// &
          quoted_real(coupling_n))
      bad = .true.
    end if
    call next_card(rd, card2, got, keep_blank=.true.)
    if (got) then
      call read_layout_card(rd, card2, KEY, 2, f)
      cmo = real_field(f, 'CMO')
      mat%con1 = int_field(f, 'CON1')
      mat%con2 = int_field(f, 'CON2')
      bad = bad .or. card2%bad
      if (.not. card2%bad) then
        mat%cmo = nint(cmo)
        if (cmo == -1.0_wp) then
          call card_error(card2, who//'field CMO = -1 (constraints in a local coordinate '// &
              'system) is not supported; use CMO = 1 (global directions)')
          bad = .true.
        else if (cmo /= 0.0_wp .and. cmo /= 1.0_wp) then
          call card_error(card2, who//'field CMO must be -1, 0 or 1 '//quoted_real(cmo))
          bad = .true.
        else if (mat%cmo == 1 .and. (mat%con1 < 0 .or. mat%con1 > 7 .or. mat%con2 < 0 .or. &
                 mat%con2 > 7)) then
          call card_error(card2, who//'fields CON1/CON2 must be constraint codes 0 to 7 '// &
              '(got '//itoa(mat%con1)//' and '//itoa(mat%con2)//')')
          bad = .true.
        else if (mat%cmo == 0) then
          mat%con1 = 0
          mat%con2 = 0
        end if
      end if
      call next_card(rd, card3, got, keep_blank=.true.)   ! card 3: output axes, unused
    end if
    if (.not. bad) call add_material(model, mat)
    call reject_extra_cards(rd, 'material '//itoa(mat%id))
  end subroutine read_mat_rigid

  !> MID of the last material card read, and forget it (0: none since the last call).
  integer function last_material_id()
    last_material_id = last_mid
    last_mid = 0
  end function last_material_id

  !> Card 1 of a material keyword whose layout is a table (mefem_card_layouts): read, its MID
  !> and RO taken and checked (check_mid_ro); got is false when the card is missing (reported
  !> with layout, the field names).
  subroutine first_layout_card(rd, card, got, keyword, layout, fields, mat)
    type(reader_t), intent(inout) :: rd          !< reading state
    type(card_t), intent(inout) :: card          !< the card
    logical, intent(out) :: got                  !< the card exists
    character(len=*), intent(in) :: keyword      !< keyword of the table (no '*')
    character(len=*), intent(in) :: layout       !< field names, for the message
    type(card_fields_t), intent(out) :: fields   !< its values
    type(material_t), intent(inout) :: mat       !< MID, RO and the source set
    call next_card(rd, card, got)
    if (.not. got) then
      call keyword_error(rd, 'missing card 1 ('//layout//')')
      return
    end if
    call read_layout_card(rd, card, keyword, 1, fields)
    mat%id = int_field(fields, 'MID')
    last_mid = mat%id
    mat%density = real_field(fields, 'RO')
    call check_mid_ro(card, mat)
  end subroutine first_layout_card

  !> The source of a material and the checks of its MID and RO (positive).
  subroutine check_mid_ro(card, mat)
    type(card_t), intent(inout) :: card          !< card 1 of the material
    type(material_t), intent(inout) :: mat       !< the material
    mat%src = source_t(card%file, card%line)
    if (card%bad) return
    if (mat%id <= 0) then
      call card_error(card, 'field MID: material id must be positive (got '//itoa(mat%id)//')')
      card%bad = .true.
    else if (mat%density <= 0.0_wp) then
      call card_error(card, 'material '//itoa(mat%id)//': field RO (density) must be > 0 '// &
          quoted_real(mat%density))
      card%bad = .true.
    end if
  end subroutine check_mid_ro

  !> E > 0 (when it is an input) and -1 < PR < 0.5.
  subroutine check_elastic(card, mat, e_given)
    type(card_t), intent(inout) :: card          !< card holding E and PR
    type(material_t), intent(in) :: mat          !< the material
    logical, intent(in) :: e_given               !< E is a field of the card
    if (e_given .and. mat%young <= 0.0_wp) then
      call card_error(card, 'material '//itoa(mat%id)//': field E (Young''s modulus) must '// &
          'be > 0 '//quoted_real(mat%young))
      card%bad = .true.
    end if
    if (mat%poisson <= -1.0_wp .or. mat%poisson >= 0.5_wp) then
      call card_error(card, 'material '//itoa(mat%id)//': field PR (Poisson''s ratio) must '// &
          'be > -1 and < 0.5 '//quoted_real(mat%poisson))
      card%bad = .true.
    end if
  end subroutine check_elastic

  !> Append a material.
  subroutine add_material(model, mat)
    type(model_t), intent(inout) :: model      !< model appended to
    type(material_t), intent(in) :: mat        !< the material
    type(material_t), allocatable :: grown(:)
    if (.not. allocated(model%materials)) allocate(model%materials(0))
    if (model%n_materials == size(model%materials)) then
      allocate(grown(max(8, 2*model%n_materials)))
      grown(1:model%n_materials) = model%materials(1:model%n_materials)
      call move_alloc(grown, model%materials)
    end if
    model%n_materials = model%n_materials + 1
    model%materials(model%n_materials) = mat
  end subroutine add_material

end module mefem_read_materials
