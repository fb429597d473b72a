/* test_trajectory_identity.c - the trajectory model's identity (the key of
 * the result store) follows the content of what the model reads: the
 * trajectory file's text and the profile as read (from a CSV file here), not
 * the file's name.  Before, it was the name alone, and an edited file
 * (a cliff raised from 20 to 40 m) was served from the store. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rockfuzz/trajectory.h"

static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    assert_int_equal(fclose(f), 0);
}

static char *identity_of(const char *path)
{
    rf_traj_spec spec;
    rf_error err = {0};
    if (rf_traj_load(path, &spec, &err) != RF_OK)
        fail_msg("%s", err.msg);
    rf_model model;
    if (rf_traj_model_create(&spec, 0, NULL, NULL, &model, &err) != RF_OK)
        fail_msg("%s", err.msg);
    char *id = strdup(model.identity);
    rf_model_free(&model);
    rf_traj_spec_free(&spec);
    return id;
}

static const char *cliff =
    "name: cliff\n"
    "profile: {points: [[0, %g], [10, 0], [60, 0]], material: rock}\n"
    "materials: {rock: {R_n: 0.4, R_t: 0.8, friction_angle: 30}}\n"
    "block: {shape: point, mass: 1000}\n"
    "release: {x: 0.5, y: %g}\n"
    "samples: 10\n";

static void test_edited_file_changes_identity(void **state)
{
    (void)state;
    char text[1024];
    snprintf(text, sizeof text, cliff, 20.0, 21.0);
    write_file("ident_cliff.yaml", text);
    char *a = identity_of("ident_cliff.yaml");
    snprintf(text, sizeof text, cliff, 40.0, 41.0); /* the cliff raised */
    write_file("ident_cliff.yaml", text);
    char *b = identity_of("ident_cliff.yaml");
    assert_string_not_equal(a, b);
    snprintf(text, sizeof text, cliff, 20.0, 21.0); /* back as it was: the same identity */
    write_file("ident_cliff.yaml", text);
    char *c = identity_of("ident_cliff.yaml");
    assert_string_equal(a, c);
    free(a), free(b), free(c);
}

static void test_edited_profile_csv_changes_identity(void **state)
{
    (void)state;
    write_file("ident_csv.yaml", "name: csv\nprofile: {csv: ident_profile.csv, material: rock}\n"
                                 "materials: {rock: {R_n: 0.4, R_t: 0.8, friction_angle: 30}}\n"
                                 "block: {shape: point, mass: 1000}\nrelease: {x: 0.5, y: 21}\nsamples: 10\n");
    write_file("ident_profile.csv", "x,y\n0,20\n10,0\n60,0\n");
    char *a = identity_of("ident_csv.yaml");
    write_file("ident_profile.csv", "x,y\n0,20\n10,0\n60,-1\n"); /* the YAML text is unchanged */
    char *b = identity_of("ident_csv.yaml");
    assert_string_not_equal(a, b);
    free(a), free(b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_edited_file_changes_identity),
        cmocka_unit_test(test_edited_profile_csv_changes_identity),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
