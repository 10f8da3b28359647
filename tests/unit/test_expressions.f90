!> Expressions of *PARAMETER_EXPRESSION (mefem_expressions): every operator, precedence and
!> associativity, nested parentheses, every function, parameters and pi, each checked against
!> the same formula written in Fortran; every error message (unknown names, argument counts,
!> syntax with its column, domain errors, overflow). Then tests/decks/good/
!> kw_parameter_expression.k is read and the computed parameters are found in the model.
program test_expressions
  use mefem_kinds, only: wp
  use mefem_testing, only: test_start, test_finish, check, check_close, check_equal, project_root
  use mefem_errors, only: reset_input_errors
  use mefem_parameters, only: parameter_define, parameters_clear
  use mefem_expressions, only: evaluate_expression
  use mefem_model, only: model_t
  use mefem_keyword_reader, only: read_deck
  implicit none

  real(wp), parameter :: TIGHT = 4.0e-16_wp
  real(wp) :: pi, a, x
  integer :: n

  call test_start('expressions')
  pi = 4.0_wp*atan(1.0_wp)
  call parameters_clear()
  call parameter_define('a', 'R', '2.5')
  call parameter_define('N', 'I', '3')
  call parameter_define('lbl', 'C', 'some text')
  call parameter_define('small', 'R', '8.9-3')      ! *PARAMETER's compact exponent: 8.9e-3
  a = 2.5_wp
  n = 3
  x = 0.3_wp

  ! numbers
  call expect('7', 7.0_wp)
  call expect('2.5e2', 2.5e2_wp)
  call expect('1e-3', 1.0e-3_wp)
  call expect('2.0d0', 2.0_wp)
  call expect('.5', 0.5_wp)
  call expect('1.5E+1', 15.0_wp)
  call expect(' 1 +  2 ', 3.0_wp)
  call expect('8.9-3', 8.9_wp - 3.0_wp)            ! in an expression, a subtraction
  ! precedence and associativity
  call expect('1+2*3', 1.0_wp + 2.0_wp*3.0_wp)
  call expect('(1+2)*3', (1.0_wp + 2.0_wp)*3.0_wp)
  call expect('10-4-3', 10.0_wp - 4.0_wp - 3.0_wp)
  call expect('10/4/2', 10.0_wp/4.0_wp/2.0_wp)
  call expect('2**3**2', 2.0_wp**3**2)
  call expect('2^3^2', 2.0_wp**3**2)
  call expect('2*3**2', 2.0_wp*3.0_wp**2)
  call expect('2**3*2', 2.0_wp**3*2.0_wp)
  call expect('-2**2', -2.0_wp**2)
  call expect('(-2)**2', (-2.0_wp)**2)
  call expect('(-2)**3', (-2.0_wp)**3)
  call expect('2**-1', 0.5_wp)
  call expect('-2**-2', -0.25_wp)
  call expect('-3*-2', 6.0_wp)
  call expect('+5', 5.0_wp)
  call expect('2**0.5', 2.0_wp**0.5_wp)
  call expect('0**0', 1.0_wp)
  call expect('(-1)**1e10', 1.0_wp)
  call expect('6/2*3', 6.0_wp/2.0_wp*3.0_wp)
  call expect('1-2+3', 1.0_wp - 2.0_wp + 3.0_wp)
  call expect('((((1+2))*(3-(4/(2+2)))))', ((((1.0_wp + 2.0_wp))*(3.0_wp - &
                                           (4.0_wp/(2.0_wp + 2.0_wp))))))
  call expect('2*(3+(4-(5*(6-(7/(8+9))))))', 2.0_wp*(3.0_wp + (4.0_wp - (5.0_wp*(6.0_wp - &
                                              (7.0_wp/(8.0_wp + 9.0_wp)))))))
  ! parameters (with and without &, any case) and pi
  call expect('a*2', a*2.0_wp)
  call expect('&a + n', a + n)
  call expect('A*&N - &n**2', a*n - n**2)
  call expect('small', 8.9e-3_wp)
  call expect('pi', pi)
  call expect('2*PI*a', 2.0_wp*pi*a)
  call expect('sqrt(a**2 + n**2)/max(a, n) - atan2(n, -a)*180/pi', &
              sqrt(a**2 + n**2)/max(a, real(n, wp)) - atan2(real(n, wp), -a)*180.0_wp/pi)
  ! every function
  call expect('abs(-3.5)', abs(-3.5_wp))
  call expect('sqrt(2)', sqrt(2.0_wp))
  call expect('exp(1.5)', exp(1.5_wp))
  call expect('log(10)', log(10.0_wp))
  call expect('log10(2)', log10(2.0_wp))
  call expect('sin(0.3)', sin(x))
  call expect('cos(0.3)', cos(x))
  call expect('tan(0.3)', tan(x))
  call expect('asin(0.3)', asin(x))
  call expect('acos(0.3)', acos(x))
  call expect('atan(0.3)', atan(x))
  call expect('atan(1, -2)', atan2(1.0_wp, -2.0_wp))
  call expect('atan2(-1, -2)', atan2(-1.0_wp, -2.0_wp))
  call expect('sinh(0.7)', sinh(0.7_wp))
  call expect('cosh(0.7)', cosh(0.7_wp))
  call expect('tanh(0.7)', tanh(0.7_wp))
  call expect('min(3, 1, 2)', 1.0_wp)
  call expect('max(3, 1, 2, 7.5)', 7.5_wp)
  call expect('MAX(a, n)', max(a, real(n, wp)))
  call expect('mod(7.5, 2)', mod(7.5_wp, 2.0_wp))
  call expect('mod(-7, 3)', mod(-7.0_wp, 3.0_wp))
  call expect('sign(3, -1)', sign(3.0_wp, -1.0_wp))
  call expect('int(-2.7)', aint(-2.7_wp))
  call expect('aint(2.7)', aint(2.7_wp))
  call expect('nint(2.5)', anint(2.5_wp))
  call expect('nint(-2.5)', anint(-2.5_wp))
  call expect('anint(2.4)', anint(2.4_wp))
  call expect('sqrt(abs(sin(a)**2 - cos(n)))*exp(-log(2))', &
              sqrt(abs(sin(a)**2 - cos(real(n, wp))))*exp(-log(2.0_wp)))
  ! underflow is no error: the result is 0 or subnormal
  call expect('10**-400', 0.0_wp)
  call expect('1e-300/1e300', 0.0_wp)

  ! names and functions
  call expect_error('b + 1', 'unknown parameter "b" at column 1 of the expression')
  call expect_error('2*&zz', 'unknown parameter "zz" at column 3 of the expression')
  call expect_error('lbl*2', 'parameter "lbl" at column 1 of the expression is a text (C)')
  call expect_error('foo(1)', 'unknown function "foo" at column 1 of the expression')
  call expect_error('1 + sqrt', 'function "sqrt" at column 5 of the expression needs its '// &
                    'arguments in parentheses')
  call expect_error('&', '''&'' at column 1 of the expression is not followed by a parameter')
  ! argument counts
  call expect_error('atan2(1)', 'function atan2 takes 2 arguments, got 1')
  call expect_error('sqrt(1, 2)', 'function sqrt takes 1 argument, got 2')
  call expect_error('min(1)', 'function min takes at least 2 arguments, got 1')
  call expect_error('atan(1, 2, 3)', 'function atan takes 1 or 2 arguments, got 3')
  call expect_error('mod(1, 2, 3)', 'function mod takes 2 arguments, got 3')
  ! syntax, with the column
  call expect_error('', 'the expression is empty')
  call expect_error('2*(a+1))', 'unexpected '')'' at column 8 of the expression')
  call expect_error('2*(a+1', 'missing '')'' at the end of the expression (for the ''('' at '// &
                    'column 3)')
  call expect_error('max(1, 2', 'missing '')'' at the end of the expression (for the ''('' '// &
                    'of max at column 4)')
  call expect_error('max(1; 2)', 'unexpected '';'' at column 6 of the expression ('','' or '// &
                    ''')'' expected in the arguments of max)')
  call expect_error('2*', 'the expression ends where a number, a name or ''('' is expected')
  call expect_error('2 3', 'unexpected ''3'' at column 3 of the expression')
  call expect_error('2 # 3', 'unexpected ''#'' at column 3 of the expression')
  call expect_error('()', 'unexpected '')'' at column 2 of the expression')
  call expect_error('2***3', 'unexpected ''*'' at column 4 of the expression')
  call expect_error('1.2.3', '"1.2.3" at column 1 of the expression is not a valid number')
  call expect_error('1e999', '"1e999" at column 1 of the expression is not a valid number')
  ! domain errors and overflow
  call expect_error('1/0', 'division by zero at column 2 of the expression')
  call expect_error('1 + 2/(a - 2.5)', 'division by zero at column 6 of the expression')
  call expect_error('mod(1, 0)', 'mod(a, 0): division by zero at column 1')
  call expect_error('0**-1', 'division by zero: 0 to the negative power -1 at column 2')
  call expect_error('log(0)', 'log of a non-positive number (0) at column 1')
  call expect_error('2*log10(-1)', 'log10 of a non-positive number (-1) at column 3')
  call expect_error('sqrt(-4)', 'sqrt of a negative number (-4) at column 1')
  call expect_error('asin(2)', 'asin of 2, outside [-1, 1], at column 1')
  call expect_error('acos(-1.5)', 'acos of -1.5, outside [-1, 1], at column 1')
  call expect_error('atan2(0, 0)', 'atan2(0, 0) is undefined at column 1')
  call expect_error('(-8)**(1/3)', 'negative number (-8) to the non-integer power')
  call expect_error('exp(1000)', 'the result of exp at column 1 of the expression is not '// &
                    'finite')
  call expect_error('cosh(-800)', 'the result of cosh at column 1 of the expression is not '// &
                    'finite')
  call expect_error('1e300*1e300', 'the result of ''*'' at column 6 of the expression is not '// &
                    'finite')
  call expect_error('1e300/1e-300', 'the result of ''/'' at column 6')
  call expect_error('1.5e308+1.5e308', 'the result of ''+'' at column 8')
  call expect_error('-1.5e308-1.5e308', 'the result of ''-'' at column 9')
  call expect_error('10**400', 'the result of ''**'' at column 3')
  call expect_error('0.1**-400', 'the result of ''**'' at column 4')
  ! the first problem is the one reported
  call expect_error('sqrt(-1) + foo(2)', 'sqrt of a negative number')

  call check_deck()
  call test_finish()

contains

  !> The expression evaluates without error to want (relative tolerance TIGHT).
  subroutine expect(text, want)
    character(len=*), intent(in) :: text   !< the expression
    real(wp), intent(in) :: want           !< its value, computed by Fortran
    real(wp) :: got
    logical :: ok
    character(len=:), allocatable :: message
    call evaluate_expression(text, got, ok, message)
    call check(ok, '"'//text//'" evaluates', message)
    if (ok) call check_close(got, want, TIGHT, '"'//text//'" value', atol=1.0e-300_wp)
  end subroutine expect

  !> The expression is rejected with a message holding fragment.
  subroutine expect_error(text, fragment)
    character(len=*), intent(in) :: text       !< the expression
    character(len=*), intent(in) :: fragment   !< part of the expected message
    real(wp) :: got
    logical :: ok
    character(len=:), allocatable :: message
    call evaluate_expression(text, got, ok, message)
    call check(.not. ok .and. index(message, fragment) > 0, '"'//text//'" rejected: '// &
               fragment, 'got ok = '//merge('T', 'F', ok)//', message "'//message//'"')
  end subroutine expect_error

  !> tests/decks/good/kw_parameter_expression.k: the computed parameters in the model, the
  !> reals bit for bit (their text reads back exactly).
  subroutine check_deck()
    type(model_t) :: model
    integer :: n_errors
    real(wp) :: scale, side
    call parameters_clear()
    call reset_input_errors()
    call read_deck(project_root()//'/tests/decks/good/kw_parameter_expression.k', model, &
                   n_errors)
    call check_equal(n_errors, 0, 'deck: read without errors')
    if (n_errors /= 0) return
    scale = 2.0_wp
    side = sqrt(2.0_wp)*scale
    call check_equal(model%nodes%n, 4, 'deck: four nodes')
    call check_equal(model%n_materials, 1, 'deck: one material')
    call check_equal(model%n_curves, 1, 'deck: one curve')
    call check_equal(model%n_nodal_loads, 1, 'deck: one nodal load')
    if (model%nodes%n /= 4 .or. model%n_materials /= 1 .or. model%n_curves /= 1 .or. &
        model%n_nodal_loads /= 1) return
    call check(model%materials(1)%young == 210000.0_wp*(1.0_wp + 0.5_wp**2) - 2.0_wp**3**2, &
               'deck: E = e0*(1 + 0.5**2) - 2**3**2, exactly')
    call check(model%materials(1)%density == 7.8e-9_wp*min(1.0_wp, abs(-2.0_wp), 3.0_wp), &
               'deck: RO from a fixed card with commas inside min(...)')
    call check(model%nodes%x(1, 2) == side, 'deck: node 2 x = sqrt(2.0)*&scale, exactly')
    call check(model%nodes%x(2, 3) == -side/(-2.0_wp), 'deck: node 3 y from the long-format '// &
               'card, exactly')
    call check_equal(model%curves(1)%id, 4, 'deck: curve id = I nint(ncurve/2.0) + 0.4')
    call check_close(model%curves(1)%f(2), max(scale, 1.5_wp)*atan2(1.0_wp, 1.0_wp)*4.0_wp/pi, &
                     TIGHT, 'deck: curve SFO from a comma card with commas in max and atan2')
    call check_equal(model%nodal_loads(1)%dof, 3, 'deck: DOF = I mod(7, 4) from a comma card')
    call check_equal(model%nodal_loads(1)%curve_id, 4, 'deck: LCID = &lcid')
    call check(model%nodal_loads(1)%scale == -3.0_wp*scale, 'deck: SF = -&scale after the '// &
               'redefinition scale*3')
    call check(model%controls%end_time == 1.0e-3_wp*(1.0_wp + 7.0_wp), &
               'deck: ENDTIM = dt*(1 + NCURVE), exactly')
  end subroutine check_deck

end program test_expressions
